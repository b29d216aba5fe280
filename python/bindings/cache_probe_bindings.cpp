// patina._core.cache_probe: the radiance cache at point a reprojected into point b
// (render/cache/cache_probe.h), for tools/draw_radiance_cache.py and the tests, and its typed
// result CacheProbeImages: arrays of R x R texels (texel j * R + i at [j, i]).
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "bindings.h"
#include "render/cache/cache_probe.h"
#include "render/integrators/integrator.h"
#include "render/render_options.h"

namespace nb = nanobind;

namespace patina_py {
namespace {

struct CacheProbeImages {
    int resolution = 0;
    nb::object a_radiance, a_dist, a_kind, a_layer, a_surfel;
    size_t surfels = 0, silhouettes = 0;
    nb::object filled, unknown, to_trace, b_reprojected, b_radiance, b_reference;
};

// The cache's least max_depth: a path of 3 segments has a bounce, whose light the cache holds.
constexpr int kMinProbeDepth = 3;

CacheProbeImages cache_probe(nb::object scene_obj, const std::vector<float>& a, const std::vector<float>& na,
                             const std::vector<float>& b, const std::vector<float>& nb_, int resolution, float error,
                             int max_depth, uint64_t seed, int width, bool unknown_masks) {
    SceneHandle& h = nb::cast<SceneHandle&>(scene_obj);
    for (const auto* v : {&a, &na, &b, &nb_})
        if (v->size() != 3) throw std::invalid_argument("points and normals must be 3 numbers");
    if (max_depth < kMinProbeDepth)
        throw std::invalid_argument("max_depth must be at least 3 (the cache holds indirect light)");
    prepare_for_render(h);
    patina::IntegratorSettings st;
    st.max_depth = patina::path_vertices(max_depth);
    st.cache.resolution = resolution;
    st.cache.error = error;
    patina::check_cache_settings(st.cache);
    const patina::RenderKernels& k = patina::render_kernels_for(width);
    patina::CacheProbe p;
    {
        nb::gil_scoped_release release;
        k.cache_probe(h.scene, st, a.data(), na.data(), b.data(), nb_.data(), patina::stream_seed(seed), unknown_masks,
                      p);
    }
    const size_t R = static_cast<size_t>(p.resolution);
    const size_t s3[3] = {R, R, 3}, s2[2] = {R, R};
    auto rgb = [&](const std::vector<float>& v) {
        float* out;
        auto arr = new_array<float, 3>(s3, &out);
        std::copy(v.begin(), v.end(), out);
        return nb::cast(arr);
    };
    auto plane = [&](const auto& v) {
        float* out;
        auto arr = new_array<float, 2>(s2, &out);
        for (size_t i = 0; i < R * R; ++i) out[i] = static_cast<float>(v[i]);
        return nb::cast(arr);
    };
    return {p.resolution,        rgb(p.a_radiance),    plane(p.a_dist),     plane(p.a_kind),
            plane(p.a_layer),    plane(p.a_surfel),    p.surfels,           p.silhouettes,
            plane(p.filled),     plane(p.unknown),     plane(p.to_trace),   rgb(p.b_reprojected),
            rgb(p.b_radiance),   rgb(p.b_reference)};
}

}  // namespace

void bind_cache_probe(nb::module_& m) {
    using P = CacheProbeImages;
    nb::class_<P>(m, "CacheProbeImages", "A cache point built at A and reprojected into B (cache_probe()).")
        .def_ro("resolution", &P::resolution, "R: texels per side of the hemispheres")
        .def_ro("a_radiance", &P::a_radiance, "(R, R, 3) A's texture: incident indirect radiance")
        .def_ro("a_dist", &P::a_dist, "(R, R) A's texels' hit distance (inf: none)")
        .def_ro("a_kind", &P::a_kind, "(R, R) what each texel of A saw: 0 hit, 1 miss, 2 under the surface")
        .def_ro("a_layer", &P::a_layer, "(R, R) the depth layer of each hit (-1: none)")
        .def_ro("a_surfel", &P::a_surfel, "(R, R) the surfel of each hit (-1: none)")
        .def_ro("surfels", &P::surfels, "A's surfels (merged blocks of texels)")
        .def_ro("silhouettes", &P::silhouettes, "A's silhouette texels")
        .def_ro("filled", &P::filled, "(R, R) B's texels the reprojection filled (1)")
        .def_ro("unknown", &P::unknown, "(R, R) B's texels the reprojection cannot know (1)")
        .def_ro("to_trace", &P::to_trace, "(R, R) B's texels left to trace (1)")
        .def_ro("b_reprojected", &P::b_reprojected, "(R, R, 3) radiance reprojected into B (-1: left to trace)")
        .def_ro("b_radiance", &P::b_radiance, "(R, R, 3) B's radiance after tracing its holes")
        .def_ro("b_reference", &P::b_reference, "(R, R, 3) B's own hemisphere traced in full");
    m.def("cache_probe", &cache_probe, nb::arg("scene"), nb::arg("a"), nb::arg("a_normal"), nb::arg("b"),
          nb::arg("b_normal"), nb::arg("resolution") = patina::CacheSettings{}.resolution,
          nb::arg("error") = patina::CacheSettings{}.error, nb::arg("max_depth") = kMinProbeDepth,
          nb::arg("seed") = 0, nb::arg("width") = 0, nb::arg("unknown_masks") = true,
          "The radiance cache at point a reprojected into point b (max_depth: the scene file's convention, at "
          "least 3): textures and masks (docs/radiance-cache.md).");
}

}  // namespace patina_py
