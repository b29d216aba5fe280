// Shared helpers of the nanobind module patina._core.
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cstddef>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "brdf/rgl/rgl_view.h"
#include "brdf/table.h"
#include "fit/lobe_kernels.h"
#include "render/accel/bvh.h"
#include "render/accel/kdtree.h"
#include "render/lights/grid2.h"
#include "render/scene.h"

namespace patina_py {

namespace nb = nanobind;

// A numpy array that owns a fresh buffer of `count` elements (freed with the array).
template <class T, size_t Dims>
nb::ndarray<nb::numpy, T, nb::ndim<Dims>> new_array(const size_t (&shape)[Dims], T** data) {
    size_t count = 1;
    for (size_t d : shape) count *= d;
    T* buffer = new T[count > 0 ? count : 1];
    nb::capsule owner(buffer, [](void* p) noexcept { delete[] static_cast<T*>(p); });
    *data = buffer;
    return nb::ndarray<nb::numpy, T, nb::ndim<Dims>>(buffer, Dims, shape, owner);
}

// A dict of named values (statistics handed to Python), in the order given.
inline nb::dict dict_of(std::initializer_list<std::pair<const char*, nb::object>> items) {
    nb::dict d;
    for (const auto& [key, value] : items) d[key] = value;
    return d;
}

template <class T>
nb::ndarray<nb::numpy, T, nb::ndim<1>> copy_vector(const T* src, size_t n) {
    T* dst;
    auto a = new_array<T, 1>({n}, &dst);
    if (n) std::memcpy(dst, src, n * sizeof(T));
    return a;
}

// patina._core.Table: a checked, immutable table with the view the kernels read, prepared once.
struct TableHandle {
    patina::Table table;
    patina::PreparedTable prepared;
    explicit TableHandle(patina::Table t) : table(std::move(t)), prepared(patina::prepare(table)) {}
};

// patina._core.RglBsdf: an RGL material's arrays (brdf_rgl_bindings.cpp) and the view the RGL
// kernels and the renderer's RGL material read.
struct RglWarpArrays {
    std::vector<float> data, marginal, conditional;
};

struct RglHandle {
    std::vector<float> theta_i, phi_i, ndf, sigma, values;
    RglWarpArrays vndf, luminance;
    patina::RglView view;
};

// patina._core.Accel: a kd-tree over triangles, and the BVH over the same triangles, built
// when first asked for (renders and `bvh=True` queries), once.
struct Accel {
    patina::KdTree tree;
    std::unique_ptr<patina::Bvh> bvh;
    std::once_flag bvh_once;
};

// The accel's BVH, built on first use; callers hold the GIL (released while building or waiting).
const patina::Bvh& bvh_of(Accel& a);

// patina._core.Grid2: a 2-D table (a goniometric light's candela over C-plane and gamma
// angles), checked and kept; evaluated by the render kernels' grid2_eval at any width, read by
// the renderer's lights and the lighting calculations' luminaires.
struct Grid2Handle {
    std::vector<float> x, y, values;
    patina::Grid2View view() const {
        return {x.data(), static_cast<int>(x.size()), y.data(), static_cast<int>(y.size()), values.data()};
    }
};

// A mixture's parameters from its kernel name (e.g. "ggx", "ggx+coat") and flat values:
// rho r g b, then per lobe its shape (r g b when per_channel) and weight r g b; with a
// coat, coat alpha and eta last. Throws std::invalid_argument.
patina::MixtureParams mixture_params(const std::string& kind, const std::vector<float>& values, bool per_channel);

// patina._core.RenderScene: the scene with references to everything its pointers point into.
struct SceneHandle {
    patina::RenderScene scene;
    std::vector<nb::object> keep;  // arrays, tables and the accel the pointers point into
};

// Before a render, a sensor or cache probe: every triangle's material checked, the light
// selection prepared (render_bindings.cpp). Throws std::invalid_argument.
void prepare_for_render(SceneHandle& h);

void bind_table(nb::module_& m);
void bind_rgl(nb::module_& m);
void bind_accel(nb::module_& m);
void bind_fit(nb::module_& m);
void bind_render(nb::module_& m);
void bind_lighting(nb::module_& m);
void bind_render_job(nb::module_& m);
void bind_cache_probe(nb::module_& m);

}  // namespace patina_py
