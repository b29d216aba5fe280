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

patina::LambertGgxParams params(const std::vector<float>& v) {
    if (v.size() != 7) throw std::invalid_argument("lambert+ggx takes 7 parameters: rho r g b, alpha, f0 r g b");
    return patina::LambertGgxParams{{v[0], v[1], v[2]}, v[3], {v[4], v[5], v[6]}};
}

nb::object eval(const std::vector<float>& p, Rows wi, Rows wo, int width) {
    const size_t n = wi.shape(0);
    if (wo.shape(0) != n) throw std::invalid_argument("wi and wo have different numbers of rows");
    const patina::LambertGgxParams q = params(p);
    const patina::LobeKernels& k = patina::lobe_kernels_for(width);
    float* out;
    const size_t shape[2] = {n, 3};
    auto result = new_array<float, 2>(shape, &out);
    {
        nb::gil_scoped_release release;
        k.eval_lambert_ggx(q, wi.data(), wo.data(), out, n);
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

double loss(const Samples& s, const std::vector<float>& p, const std::string& kind, int width, int threads) {
    patina::LossKind k;
    if (kind == "l2cos") k = patina::LossKind::CosineL2;
    else if (kind == "log") k = patina::LossKind::Log;
    else throw std::invalid_argument("loss '" + kind + "': expected l2cos or log");
    const patina::LambertGgxParams q = params(p);
    nb::gil_scoped_release release;
    return patina::lambert_ggx_loss(q, s.view(), k, width, threads);
}

}  // namespace

void bind_fit(nb::module_& m) {
    m.def("lambert_ggx_eval", &eval, nb::arg("params"), nb::arg("wi"), nb::arg("wo"), nb::arg("width") = 0,
          "Lambert + GGX (height-correlated Smith, Schlick Fresnel) at (n, 3) direction pairs -> (n, 3) RGB.");
    nb::class_<Samples>(m, "FitSamples", "A table's samples for fitting: directions, measured RGB, weights.")
        .def(nb::new_(&make_samples), nb::arg("wi"), nb::arg("wo"), nb::arg("measured"), nb::arg("weight"))
        .def_prop_ro("count", [](const Samples& s) { return s.weight.size(); })
        .def("lambert_ggx_loss", &loss, nb::arg("params"), nb::arg("loss") = "l2cos", nb::arg("width") = 0,
             nb::arg("threads") = 0, "Mean loss of Lambert + GGX with these 7 parameters over the samples.");
}

}  // namespace patina_py
