// patina._core: the analytic lobes and fitting losses.
#include <nanobind/stl/string.h>
#include <nanobind/stl/unique_ptr.h>
#include <nanobind/stl/vector.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bindings.h"
#include "fit/lobe_kernels.h"
#include "fit/loss.h"

namespace nb = nanobind;

namespace patina_py {
namespace {

using Rows = nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using FloatVector = nb::ndarray<const float, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

// What a lobe's entry in the parameter vector holds, in order, before its weight r g b.
enum class Field { Shape, ShapeY, Cx, Cy, Cz, Cxy };

struct LobeLayout {
    patina::LobeKind kind;
    std::vector<Field> fields;  // Shape and ShapeY take r g b when per channel, the rest one value
};

LobeLayout lobe_layout(const std::string& name) {
    using patina::LobeKind;
    if (name == "ggx") return {LobeKind::GGX, {Field::Shape}};
    if (name == "beckmann") return {LobeKind::Beckmann, {Field::Shape}};
    if (name == "blinnphong") return {LobeKind::BlinnPhong, {Field::Shape}};
    if (name == "ward") return {LobeKind::Ward, {Field::Shape}};
    if (name == "ashikhmin") return {LobeKind::AshikhminShirley, {Field::Shape}};
    if (name == "ward-aniso") return {LobeKind::Ward, {Field::Shape, Field::ShapeY}};
    if (name == "ashikhmin-aniso") return {LobeKind::AshikhminShirley, {Field::Shape, Field::ShapeY}};
    if (name == "lafortune") return {LobeKind::Lafortune, {Field::Cxy, Field::Cz, Field::Shape}};
    if (name == "lafortune-aniso") return {LobeKind::Lafortune, {Field::Cx, Field::Cy, Field::Cz, Field::Shape}};
    throw std::invalid_argument("lobe '" + name +
                                "': expected ggx, beckmann, blinnphong, ward, ashikhmin, ward-aniso, "
                                "ashikhmin-aniso, lafortune or lafortune-aniso");
}

}  // namespace

// params: rho r g b, then per lobe its fields (lobe_layout: the shape, r g b when per_channel;
// ward-aniso / ashikhmin-aniso alpha_x alpha_y / nu nv; lafortune Cx=Cy Cz n, lafortune-aniso
// Cx Cy Cz n) and its weight r g b; with a coat, coat alpha and eta last.
patina::MixtureParams mixture_params(const std::string& kind, const std::vector<float>& in, bool per_channel) {
    patina::MixtureParams p;
    std::string name = kind;
    std::vector<float> v = in;
    const std::string suffix = "+coat";
    if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
        name.resize(name.size() - suffix.size());
        if (v.size() < 2) throw std::invalid_argument("a coated mixture ends with coat alpha and eta");
        p.coat = true;
        p.coat_eta = v.back();
        v.pop_back();
        p.coat_alpha = v.back();
        v.pop_back();
    }
    const LobeLayout layout = lobe_layout(name);
    p.kind = layout.kind;
    size_t stride = 3;
    for (Field f : layout.fields) stride += (f == Field::Shape || f == Field::ShapeY) && per_channel ? 3 : 1;
    if (v.size() < 3 + stride || (v.size() - 3) % stride != 0 || (v.size() - 3) / stride > patina::kMaxLobes)
        throw std::invalid_argument("a " + name + " mixture takes rho r g b and, per lobe (1 to 3), " +
                                    std::to_string(stride - 3) + " shape values and a weight r g b");
    p.lobes = static_cast<int>((v.size() - 3) / stride);
    for (int c = 0; c < 3; ++c) p.rho[c] = v[c];
    for (int l = 0; l < p.lobes; ++l) {
        const float* at = &v[3 + stride * l];
        bool has_y = false;
        for (Field f : layout.fields) {
            const int n = (f == Field::Shape || f == Field::ShapeY) && per_channel ? 3 : 1;
            for (int c = 0; c < 3; ++c) {
                const float x = at[n == 3 ? c : 0];
                switch (f) {
                    case Field::Shape: p.shape[l][c] = x; break;
                    case Field::ShapeY: p.shape_y[l][c] = x; break;
                    case Field::Cx: p.lafortune_c[l][0] = x; break;
                    case Field::Cy: p.lafortune_c[l][1] = x; break;
                    case Field::Cz: p.lafortune_c[l][2] = x; break;
                    case Field::Cxy: p.lafortune_c[l][0] = p.lafortune_c[l][1] = x; break;
                }
            }
            has_y |= f == Field::ShapeY;
            at += n;
        }
        for (int c = 0; c < 3; ++c) {
            if (!has_y) p.shape_y[l][c] = p.shape[l][c];  // isotropic: the same shape both ways
            p.weight[l][c] = at[c];
        }
    }
    return p;
}

namespace {

nb::object eval(const std::string& kind, const std::vector<float>& p, Rows wi, Rows wo, int width, bool per_channel) {
    const size_t n = wi.shape(0);
    if (wo.shape(0) != n) throw std::invalid_argument("wi and wo have different numbers of rows");
    const patina::MixtureParams q = mixture_params(kind, p, per_channel);
    const patina::LobeKernels& k = patina::lobe_kernels_for(width);
    float* out;
    const size_t shape[2] = {n, 3};
    auto result = new_array<float, 2>(shape, &out);
    {
        nb::gil_scoped_release release;
        k.eval_mixture(q, wi.data(), wo.data(), out, n);
    }
    return nb::cast(result);
}

// Holds a copy of the samples, so a fit can evaluate its loss many times without re-passing them.
struct Samples {
    std::vector<float> wi, wo, measured, weight;
    patina::FitSamples view() const {
        return patina::FitSamples{wi.data(), wo.data(), measured.data(), weight.data(), weight.size()};
    }
};

std::unique_ptr<Samples> make_samples(Rows wi, Rows wo, Rows measured, FloatVector weight) {
    const size_t n = wi.shape(0);
    if (wo.shape(0) != n || measured.shape(0) != n || weight.shape(0) != n)
        throw std::invalid_argument("wi, wo, measured and weight need the same number of rows");
    auto s = std::make_unique<Samples>();
    s->wi.assign(wi.data(), wi.data() + 3 * n);
    s->wo.assign(wo.data(), wo.data() + 3 * n);
    s->measured.assign(measured.data(), measured.data() + 3 * n);
    s->weight.assign(weight.data(), weight.data() + n);
    return s;
}

double loss(const Samples& s, const std::string& kind, const std::vector<float>& p, const std::string& loss_name,
            int width, int threads, bool per_channel) {
    patina::LossKind k;
    if (loss_name == "l2cos") k = patina::LossKind::CosineL2;
    else if (loss_name == "log") k = patina::LossKind::Log;
    else throw std::invalid_argument("loss '" + loss_name + "': expected l2cos or log");
    const patina::MixtureParams q = mixture_params(kind, p, per_channel);
    nb::gil_scoped_release release;
    return patina::mixture_loss(q, s.view(), k, width, threads);
}

}  // namespace

void bind_fit(nb::module_& m) {
    m.def("mixture_eval", &eval, nb::arg("lobe"), nb::arg("params"), nb::arg("wi"), nb::arg("wo"),
          nb::arg("width") = 0, nb::arg("per_channel") = false,
          "Lambert + 1-3 specular lobes (ggx, beckmann, blinnphong, ward, ashikhmin, ward-aniso, "
          "ashikhmin-aniso, lafortune, lafortune-aniso; '+coat' adds a clear coat) at (n, 3) direction pairs "
          "-> (n, 3) RGB. params: rho r g b, then per lobe its shape (ward-aniso alpha_x alpha_y, "
          "ashikhmin-aniso nu nv, lafortune Cxy Cz n, lafortune-aniso Cx Cy Cz n; alpha, alpha_y, nu, nv, n "
          "r g b when per_channel) and weight r g b, then (coat) its alpha and eta.");
    nb::class_<Samples>(m, "FitSamples", "A table's samples for fitting: directions, measured RGB, weights.")
        .def(nb::new_(&make_samples), nb::arg("wi"), nb::arg("wo"), nb::arg("measured"), nb::arg("weight"))
        .def_prop_ro("count", [](const Samples& s) { return s.weight.size(); })
        .def("mixture_loss", &loss, nb::arg("lobe"), nb::arg("params"), nb::arg("loss") = "l2cos",
             nb::arg("width") = 0, nb::arg("threads") = 0, nb::arg("per_channel") = false,
             "Mean loss of the mixture over the samples.");
}

}  // namespace patina_py
