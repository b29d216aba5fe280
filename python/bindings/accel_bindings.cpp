// patina._core.Accel: a kd-tree over triangles and its packet ray tracer.
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/unique_ptr.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bindings.h"
#include "render/accel/kdtree.h"
#include "render/accel/ray_recorder.h"
#include "render/accel/trace_kernels.h"

namespace nb = nanobind;

namespace patina_py {
namespace {

using Vertices = nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using Indices = nb::ndarray<const int32_t, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using Rays3 = nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using FloatVector = nb::ndarray<const float, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

using SphereRows = nb::ndarray<const float, nb::shape<-1, 4>, nb::c_contig, nb::device::cpu>;
using SphereFrames = nb::ndarray<const float, nb::shape<-1, 3, 3>, nb::c_contig, nb::device::cpu>;

// The analytic spheres (S, 4: centre, radius) and their object frames (S, 3, 3: the object's
// x, y, z axes in the world, rows; identity when None), primitives triangle_count() on.
patina::SphereSet sphere_set(nb::object spheres, nb::object frames, size_t triangle_count) {
    patina::SphereSet set;
    set.prim_base = static_cast<int32_t>(triangle_count);
    if (spheres.is_none()) {
        if (!frames.is_none()) throw std::invalid_argument("sphere_frames given without spheres");
        return set;
    }
    const SphereRows rows = nb::cast<SphereRows>(spheres);
    const size_t ns = rows.shape(0);
    const float* fr = nullptr;
    if (!frames.is_none()) {
        const SphereFrames f = nb::cast<SphereFrames>(frames);
        if (f.shape(0) != ns) throw std::invalid_argument("sphere_frames needs one frame per sphere");
        fr = f.data();
    }
    if (triangle_count + ns >= (size_t(1) << 30)) throw std::invalid_argument("more than 2^30 primitives");
    const float identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (size_t k = 0; k < ns; ++k) {
        try {
            set.add(rows.data() + 4 * k, rows.data()[4 * k + 3], fr ? fr + 9 * k : identity);
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument("sphere " + std::to_string(k) + ": " + e.what());
        }
    }
    return set;
}

std::unique_ptr<Accel> make_accel(Vertices vertices, Indices indices, int max_leaf, int max_depth, int threads,
                                  nb::object spheres, nb::object sphere_frames) {
    const size_t nv = vertices.shape(0), nt = indices.shape(0);
    const float* v = vertices.data();
    for (size_t i = 0; i < 3 * nv; ++i)
        if (!std::isfinite(v[i]))
            throw std::invalid_argument("vertex " + std::to_string(i / 3) + " is not finite");
    const int32_t* f = indices.data();
    for (size_t i = 0; i < 3 * nt; ++i)
        if (f[i] < 0 || static_cast<size_t>(f[i]) >= nv)
            throw std::invalid_argument("triangle " + std::to_string(i / 3) + " refers to vertex " +
                                        std::to_string(f[i]) + ", the mesh has " + std::to_string(nv));
    if (nt >= (size_t(1) << 30)) throw std::invalid_argument("more than 2^30 triangles");
    patina::SphereSet set = sphere_set(spheres, sphere_frames, nt);
    patina::KdBuildOptions opt;
    if (max_leaf > 0) opt.max_leaf = max_leaf;
    if (max_depth > 0) opt.max_depth = std::min(max_depth, 100);
    opt.threads = threads;
    auto accel = std::make_unique<Accel>();
    {
        nb::gil_scoped_release release;
        accel->tree = patina::build_kdtree(v, nv, f, nt, opt);
    }
    accel->tree.spheres = std::move(set);
    return accel;
}

}  // namespace

const patina::Bvh& bvh_of(Accel& a) {
    // without the GIL while waiting too: a thread holding it must not block the one building
    nb::gil_scoped_release release;
    std::call_once(a.bvh_once, [&] {
        a.bvh = std::make_unique<patina::Bvh>(patina::build_bvh(a.tree.triangles.data(), a.tree.triangle_count()));
        a.bvh->spheres = a.tree.spheres;
    });
    return *a.bvh;
}

namespace {

patina::RayBatch ray_batch(Rays3 origins, Rays3 directions, float tmin, nb::object tmax) {
    const size_t n = origins.shape(0);
    if (directions.shape(0) != n)
        throw std::invalid_argument("origins has " + std::to_string(n) + " rows but directions has " +
                                    std::to_string(directions.shape(0)));
    if (!(tmin >= 0.0f) || !std::isfinite(tmin)) throw std::invalid_argument("tmin must be finite and >= 0");
    patina::RayBatch rays{origins.data(), directions.data(), tmin, nullptr, std::numeric_limits<float>::infinity()};
    if (!tmax.is_none()) {
        if (nb::isinstance<nb::float_>(tmax) || nb::isinstance<nb::int_>(tmax)) {
            rays.tmax_all = nb::cast<float>(tmax);
            if (std::isnan(rays.tmax_all)) throw std::invalid_argument("tmax is NaN");
        } else {
            auto arr = nb::cast<FloatVector>(tmax);
            if (arr.shape(0) != n) throw std::invalid_argument("tmax must hold one value per ray");
            rays.tmax = arr.data();
        }
    }
    const size_t bad = patina::first_invalid_ray(rays, n);
    if (bad < n)
        throw std::invalid_argument("ray " + std::to_string(bad) +
                                    ": origin and direction must be finite, the direction non-zero, tmax not NaN");
    return rays;
}

using FloatOut = nb::ndarray<float, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using IntOut = nb::ndarray<int32_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using NormalOut = nb::ndarray<float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;

nb::tuple intersect(Accel& a, Rays3 origins, Rays3 directions, float tmin, nb::object tmax, int width,
                    int threads, nb::object out, bool bvh) {
    // keep a converted tmax array alive for the duration of the call
    nb::object tmax_arr = tmax;
    if (!tmax.is_none() && !nb::isinstance<nb::float_>(tmax) && !nb::isinstance<nb::int_>(tmax))
        tmax_arr = nb::cast(nb::cast<FloatVector>(tmax));
    const patina::RayBatch rays = ray_batch(origins, directions, tmin, tmax_arr);
    const size_t n = origins.shape(0);
    float *t, *u, *v, *normal;
    int32_t* prim;
    nb::tuple result;
    if (out.is_none()) {
        auto t_arr = new_array<float, 1>({n}, &t);
        auto u_arr = new_array<float, 1>({n}, &u);
        auto v_arr = new_array<float, 1>({n}, &v);
        auto prim_arr = new_array<int32_t, 1>({n}, &prim);
        const size_t shape[2] = {n, 3};
        auto normal_arr = new_array<float, 2>(shape, &normal);
        result = nb::make_tuple(t_arr, prim_arr, u_arr, v_arr, normal_arr);
    } else {
        // caller-provided (t, prim, u, v, normal): no allocation, as a render loop wants
        result = nb::cast<nb::tuple>(out);
        if (result.size() != 5) throw std::invalid_argument("out must be a tuple (t, prim, u, v, normal)");
        auto ot = nb::cast<FloatOut>(result[0]);
        auto op = nb::cast<IntOut>(result[1]);
        auto ou = nb::cast<FloatOut>(result[2]);
        auto ov = nb::cast<FloatOut>(result[3]);
        auto on = nb::cast<NormalOut>(result[4]);
        if (ot.shape(0) != n || op.shape(0) != n || ou.shape(0) != n || ov.shape(0) != n || on.shape(0) != n)
            throw std::invalid_argument("out arrays must hold one row per ray");
        t = ot.data();
        prim = op.data();
        u = ou.data();
        v = ov.data();
        normal = on.data();
    }
    const patina::Bvh* wide = bvh ? &bvh_of(a) : nullptr;
    {
        nb::gil_scoped_release release;
        const patina::HitBatch hits{t, prim, u, v};
        if (wide) patina::trace_intersect(*wide, rays, hits, n, width, threads);
        else patina::trace_intersect(a.tree, rays, hits, n, width, threads);
        patina::hit_normals(a.tree, rays, t, prim, normal, n);
    }
    return result;
}

nb::object occluded(Accel& a, Rays3 origins, Rays3 directions, nb::object tmax, float tmin, int width,
                    int threads, bool bvh) {
    nb::object tmax_arr = tmax;
    if (!tmax.is_none() && !nb::isinstance<nb::float_>(tmax) && !nb::isinstance<nb::int_>(tmax))
        tmax_arr = nb::cast(nb::cast<FloatVector>(tmax));
    const patina::RayBatch rays = ray_batch(origins, directions, tmin, tmax_arr);
    const size_t n = origins.shape(0);
    bool* out;
    auto result = new_array<bool, 1>({n}, &out);
    static_assert(sizeof(bool) == sizeof(uint8_t), "bool arrays are written as bytes");
    const patina::Bvh* wide = bvh ? &bvh_of(a) : nullptr;
    {
        nb::gil_scoped_release release;
        uint8_t* blocked = reinterpret_cast<uint8_t*>(out);
        if (wide) patina::trace_occluded(*wide, rays, blocked, n, width, threads);
        else patina::trace_occluded(a.tree, rays, blocked, n, width, threads);
    }
    return nb::cast(result);
}

// (n, 3) float32 rows copied out of a flat vector.
nb::object rows3(const std::vector<float>& v) {
    float* out;
    const size_t shape[2] = {v.size() / 3, 3};
    auto a = new_array<float, 2>(shape, &out);
    if (!v.empty()) std::memcpy(out, v.data(), v.size() * sizeof(float));
    return nb::cast(a);
}

nb::dict stop_recording() {
    patina::RecordedRays r;
    {
        nb::gil_scoped_release release;
        r = patina::stop_ray_recording();
    }
    nb::dict d;
    d["origins"] = rows3(r.origins);
    d["directions"] = rows3(r.directions);
    d["tmin"] = copy_vector(r.tmin.data(), r.tmin.size());
    d["tmax"] = copy_vector(r.tmax.data(), r.tmax.size());
    d["any_hit"] = copy_vector(r.any_hit.data(), r.any_hit.size());
    d["truncated"] = r.truncated;
    return d;
}

nb::object triangles_of(const Accel& a) {
    float* out;
    const size_t n = a.tree.triangle_count();
    const size_t shape[3] = {n, 3, 3};
    auto arr = new_array<float, 3>(shape, &out);
    if (n) std::memcpy(out, a.tree.triangles.data(), 9 * n * sizeof(float));
    return nb::cast(arr);
}

}  // namespace

void bind_accel(nb::module_& m) {
    m.def("start_ray_recording", &patina::start_ray_recording, nb::arg("limit"),
          "Records every ray the tracing kernels see from now on (at most `limit`), for the benchmark's replays.");
    m.def("stop_ray_recording", &stop_recording,
          "Stops recording: dict of origins (n, 3), directions (n, 3), tmin, tmax, any_hit (uint8, 1 for an "
          "occlusion query) and truncated (the limit was reached).");
    nb::class_<Accel>(m, "Accel",
                      "A SAH kd-tree over triangles with single-ray and 4/8-ray packet traversal, and an 8-wide "
                      "BVH over the same triangles for incoherent rays (built on first use).")
        .def(nb::new_(&make_accel), nb::arg("vertices"), nb::arg("indices"), nb::arg("max_leaf") = 0,
             nb::arg("max_depth") = 0, nb::arg("threads") = 0, nb::arg("spheres") = nb::none(),
             nb::arg("sphere_frames") = nb::none(),
             "Builds the tree from float32 (V, 3) vertices and int32 (T, 3) indices; 0 means the default. "
             "spheres: float32 (S, 4) analytic spheres (centre, radius), traced beside the triangles as "
             "primitives T .. T + S - 1; sphere_frames: float32 (S, 3, 3), each sphere's object x, y, z axes "
             "in the world (its tangents run about y), identity by default.")
        .def_prop_ro("sphere_count", [](const Accel& a) { return a.tree.spheres.size(); })
        .def_prop_ro("triangle_count", [](const Accel& a) { return a.tree.triangle_count(); })
        .def_prop_ro("node_count", [](const Accel& a) { return a.tree.nodes.size(); })
        .def_prop_ro("leaf_count", [](const Accel& a) { return a.tree.stats.leaves; })
        .def_prop_ro("empty_leaf_count", [](const Accel& a) { return a.tree.stats.empty_leaves; })
        .def_prop_ro("leaf_references", [](const Accel& a) { return a.tree.stats.leaf_refs; })
        .def_prop_ro("depth", [](const Accel& a) { return a.tree.stats.depth; })
        .def_prop_ro("build_seconds", [](const Accel& a) { return a.tree.stats.build_seconds; })
        .def("build_bvh", [](Accel& a) { return bvh_of(a).stats.build_seconds; },
             "Builds the BVH now if it is not yet built (one thread); seconds its build took.")
        .def_prop_ro("bvh_stats", [](Accel& a) {
            const patina::BvhStats& st = bvh_of(a).stats;
            return dict_of({{"nodes", nb::cast(st.nodes)},
                            {"leaves", nb::cast(st.leaves)},
                            {"blocks", nb::cast(st.blocks)},
                            {"depth", nb::cast(st.depth)},
                            {"build_seconds", nb::cast(st.build_seconds)}});
        }, "The BVH's nodes, leaves, 8-triangle blocks, depth and build seconds (built if need be).")
        .def_prop_ro("triangles", &triangles_of, "(T, 3, 3) float32 corners, in the order of the indices given")
        .def("intersect", &intersect, nb::arg("origins"), nb::arg("directions"), nb::arg("tmin") = 0.0f,
             nb::arg("tmax") = nb::none(), nb::arg("width") = 0, nb::arg("threads") = 0, nb::arg("out") = nb::none(),
             nb::arg("bvh") = false,
             "Closest hits: (t, prim, u, v, normal); t = inf and prim = -1 on a miss. Rays [i, i + width) "
             "form one packet. out: preallocated (t, prim, u, v, normal) arrays to write into. bvh: trace "
             "one ray at a time through the BVH (the width's lanes over a node's children; ties go to the "
             "least primitive index).")
        .def("occluded", &occluded, nb::arg("origins"), nb::arg("directions"), nb::arg("tmax") = nb::none(),
             nb::arg("tmin") = 0.0f, nb::arg("width") = 0, nb::arg("threads") = 0, nb::arg("bvh") = false,
             "True where something is hit with tmin < t < tmax. bvh: through the BVH, one ray at a time.");
}

}  // namespace patina_py
