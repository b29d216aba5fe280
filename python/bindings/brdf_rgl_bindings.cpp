// patina._core.RglBsdf: an RGL .bsdf material's arrays (as python/patina/table/formats/
// rgl_native.py hands them over from the checked reader) with the native evaluator, pdf and
// sampler.
#include <nanobind/stl/string.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "bindings.h"
#include "brdf/rgl/rgl_kernels.h"

namespace nb = nanobind;

namespace patina_py {
namespace {

using FloatAny = nb::ndarray<const float, nb::c_contig, nb::device::cpu>;
using Directions = nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using Uniforms = nb::ndarray<const float, nb::shape<-1, 2>, nb::c_contig, nb::device::cpu>;

// One array copied, its shape checked: `dims` sizes, -1 for any.
std::vector<float> take(const char* name, const FloatAny& a, std::initializer_list<long> dims) {
    if (a.ndim() != dims.size()) throw std::invalid_argument(std::string(name) + ": wrong number of dimensions");
    size_t d = 0;
    for (long expected : dims) {
        if (expected >= 0 && static_cast<long>(a.shape(d)) != expected)
            throw std::invalid_argument(std::string(name) + ": dimension " + std::to_string(d) + " is " +
                                        std::to_string(a.shape(d)) + ", expected " + std::to_string(expected));
        ++d;
    }
    return std::vector<float>(a.data(), a.data() + a.size());
}

RglWarpArrays take_warp(const char* name, const FloatAny& data, const FloatAny& marginal,
                        const FloatAny& conditional, long slices, patina::RglWarpView& view) {
    if (data.ndim() != 3) throw std::invalid_argument(std::string(name) + ": expected (slices, height, width)");
    const long height = static_cast<long>(data.shape(1)), width = static_cast<long>(data.shape(2));
    if (height < 2 || width < 2) throw std::invalid_argument(std::string(name) + ": grids need 2 x 2 nodes");
    RglWarpArrays w{take(name, data, {slices, height, width}), take(name, marginal, {slices, height}),
                    take(name, conditional, {slices, height, width})};
    view = {w.data.data(), w.marginal.data(), w.conditional.data(), static_cast<int>(height), static_cast<int>(width)};
    return w;
}

patina::RglGridView grid_view(const char* name, const FloatAny& a, const std::vector<float>& data) {
    if (a.shape(a.ndim() - 2) < 2 || a.shape(a.ndim() - 1) < 2)
        throw std::invalid_argument(std::string(name) + ": grids need 2 x 2 nodes");
    return {data.data(), static_cast<int>(a.shape(a.ndim() - 2)), static_cast<int>(a.shape(a.ndim() - 1))};
}

void fill_rgl(RglHandle* h, FloatAny theta_i, FloatAny phi_i, FloatAny ndf, FloatAny sigma, FloatAny vndf,
                    FloatAny vndf_marginal, FloatAny vndf_conditional, FloatAny luminance,
                    FloatAny luminance_marginal, FloatAny luminance_conditional, FloatAny values, bool isotropic,
                    bool jacobian, int reduction) {
    h->theta_i = take("theta_i", theta_i, {-1});
    h->phi_i = take("phi_i", phi_i, {-1});
    const long thetas = static_cast<long>(h->theta_i.size()), phis = static_cast<long>(h->phi_i.size());
    if (thetas < 1 || phis < 1) throw std::invalid_argument("theta_i, phi_i: at least one value each");
    h->ndf = take("ndf", ndf, {-1, -1});
    h->sigma = take("sigma", sigma, {-1, -1});
    h->values = take("values", values, {phis, thetas, patina::kRglChannels, -1, -1});
    patina::RglView& v = h->view;
    h->vndf = take_warp("vndf", vndf, vndf_marginal, vndf_conditional, phis * thetas, v.vndf);
    h->luminance = take_warp("luminance", luminance, luminance_marginal, luminance_conditional, phis * thetas,
                             v.luminance);
    v.theta_i = h->theta_i.data();
    v.phi_i = h->phi_i.data();
    v.theta_count = static_cast<int>(thetas);
    v.phi_count = static_cast<int>(phis);
    v.ndf = grid_view("ndf", ndf, h->ndf);
    v.sigma = grid_view("sigma", sigma, h->sigma);
    v.values = grid_view("values", values, h->values);
    v.isotropic = isotropic;
    v.jacobian = jacobian;
    if (reduction != 1 && reduction != 2 && reduction != 4) throw std::invalid_argument("reduction: 1, 2 or 4");
    v.reduction = reduction;
}

size_t pair_count(const Directions& wi, const Directions& wo) {
    if (wi.shape(0) != wo.shape(0)) throw std::invalid_argument("wi and wo have different numbers of rows");
    return wi.shape(0);
}

nb::object rgl_eval(const RglHandle& h, Directions wi, Directions wo, int width, int threads) {
    const size_t n = pair_count(wi, wo);
    float* out;
    nb::object result = nb::cast(new_array<float, 2>({n, static_cast<size_t>(patina::kRglChannels)}, &out));
    {
        nb::gil_scoped_release release;
        patina::rgl_eval_batch(h.view, wi.data(), wo.data(), out, n, width, threads);
    }
    return result;
}

nb::object rgl_pdf(const RglHandle& h, Directions wi, Directions wo, int width, int threads) {
    const size_t n = pair_count(wi, wo);
    float* out;
    nb::object result = nb::cast(new_array<float, 1>({n}, &out));
    {
        nb::gil_scoped_release release;
        patina::rgl_pdf_batch(h.view, wi.data(), wo.data(), out, n, width, threads);
    }
    return result;
}

nb::object rgl_sample(const RglHandle& h, Directions wi, Uniforms u, int width, int threads) {
    const size_t n = wi.shape(0);
    if (u.shape(0) != n) throw std::invalid_argument("wi and u have different numbers of rows");
    float *wo, *pdf;
    nb::object wo_array = nb::cast(new_array<float, 2>({n, size_t(3)}, &wo));
    nb::object pdf_array = nb::cast(new_array<float, 1>({n}, &pdf));
    {
        nb::gil_scoped_release release;
        std::vector<float> u1(n), u2(n);  // the kernels read each uniform as lanes of its own array
        for (size_t i = 0; i < n; ++i) {
            u1[i] = u.data()[2 * i];
            u2[i] = u.data()[2 * i + 1];
        }
        patina::rgl_sample_batch(h.view, wi.data(), u1.data(), u2.data(), wo, pdf, n, width, threads);
    }
    return nb::make_tuple(wo_array, pdf_array);
}

}  // namespace

void bind_rgl(nb::module_& m) {
    nb::class_<RglHandle>(m, "RglBsdf",
                          "An RGL .bsdf material (linear sRGB values, normalised warps) with the native "
                          "evaluator; build it with patina.table.formats.rgl_native.native_rgl.")
        .def("__init__",
             [](RglHandle* self, FloatAny theta_i, FloatAny phi_i, FloatAny ndf, FloatAny sigma, FloatAny vndf,
                FloatAny vndf_marginal, FloatAny vndf_conditional, FloatAny luminance, FloatAny luminance_marginal,
                FloatAny luminance_conditional, FloatAny values, bool isotropic, bool jacobian, int reduction) {
                 new (self) RglHandle();
                 try {
                     fill_rgl(self, theta_i, phi_i, ndf, sigma, vndf, vndf_marginal, vndf_conditional, luminance,
                              luminance_marginal, luminance_conditional, values, isotropic, jacobian, reduction);
                 } catch (...) {
                     self->~RglHandle();
                     throw;
                 }
             },
             nb::arg("theta_i"), nb::arg("phi_i"), nb::arg("ndf"), nb::arg("sigma"), nb::arg("vndf"),
             nb::arg("vndf_marginal"), nb::arg("vndf_conditional"), nb::arg("luminance"),
             nb::arg("luminance_marginal"), nb::arg("luminance_conditional"), nb::arg("values"),
             nb::arg("isotropic"), nb::arg("jacobian"), nb::arg("reduction"))
        .def("eval", &rgl_eval, nb::arg("wi"), nb::arg("wo"), nb::arg("width") = 0, nb::arg("threads") = 1,
             "f(wi, wo) (n, 3) linear sRGB in 1/sr for float32 (n, 3) unit directions; 0 below the horizon.")
        .def("pdf", &rgl_pdf, nb::arg("wi"), nb::arg("wo"), nb::arg("width") = 0, nb::arg("threads") = 1,
             "The density (n,) per steradian with which `sample` draws wo given wi.")
        .def("sample", &rgl_sample, nb::arg("wi"), nb::arg("u"), nb::arg("width") = 0, nb::arg("threads") = 1,
             "wo (n, 3) and its pdf (n,) for directions wi (n, 3) and uniform points u (n, 2); pdf 0 "
             "where the sample falls below the horizon.");
}

}  // namespace patina_py
