// A bounce's hits made shading points (an integrator's stage): grouped by material, so each
// material's points are shaded N at a time; their frames N hits at a time; the first hit's AOVs.
#pragma once

#include <algorithm>
#include <vector>

#include "core/simd/kernel_width.h"
#include "render/accel/sphere_points.h"
#include "render/integrators/integrator.h"
#include "render/integrators/wavefront_impl.h"
#include "render/scene.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// Whether hit j may become a shading point: a surface (not a light) while the path may
// still bounce (make_shading_point may still end the path there).
inline bool may_shade(const Wavefront& wavefront, const HitBatch& hits, size_t j, int depth) {
    const int32_t prim = hits.prim[j];
    // (a path whose first hit's indirect light the cache gave only looks for emission)
    const PathScratch& scratch = wavefront.scratch;
    const bool cached = depth > 0 && !scratch.cached.empty() && scratch.cached[scratch.active[j]];
    return prim >= 0 && !wavefront.scene.materials[wavefront.scene.tri_material[prim]].is<Emitter>() &&
           depth < wavefront.settings.max_depth && !cached;
}

// Hit j's geometric normal (from the winding; an analytic sphere's outwards), as
// make_shading_lanes has it before facing the viewer.
inline Vec3f hit_normal(const Wavefront& wavefront, const HitBatch& hits, size_t j, const float* tn) {
    const int32_t prim = hits.prim[j];
    const SphereSet& spheres = wavefront.scene.tree->spheres;
    if (!spheres.owns(prim)) return load_vec3(tn + 3 * static_cast<size_t>(prim));
    const int32_t i = wavefront.scratch.active[j];
    return sphere_normal<1>(spheres, prim - spheres.prim_base, load_vec3(wavefront.scratch.org.data() + 3 * i),
                            load_vec3(wavefront.scratch.dir.data() + 3 * i), hits.t[j]);
}

// Grouping by material before the points exist: the hits that become shading points
//    (not the back of a one-sided surface, where the path ends) in scratch.shade_hits, counted
//    per material (scratch.material_start: each group's first slot in scratch.sorted), so
//    make_shading_points writes each point straight into its group, in hit order (what a
//    stable counting sort of the points would give, without building and copying them twice).
inline void group_by_material(const Wavefront& wavefront, const HitBatch& hits, int depth) {
    PathScratch& scratch = wavefront.scratch;
    const size_t nm = wavefront.scene.materials.size();
    scratch.material_start.assign(nm + 1, 0);
    scratch.material_eta.resize(nm);
    scratch.material_transmissive.resize(nm);
    scratch.material_two_sided.resize(nm);
    for (size_t k = 0; k < nm; ++k) {
        const Material& m = wavefront.scene.materials[k];
        const bool transmissive = transmits(m);
        scratch.material_eta[k] = transmissive ? m.as<Dielectric>().eta : 1.0f;
        scratch.material_transmissive[k] = transmissive ? 1.0f : 0.0f;
        scratch.material_two_sided[k] = m.two_sided || transmissive ? 1.0f : 0.0f;
    }
    scratch.shade_hits.clear();
    const float* tn = wavefront.scene.tree->normals.data();
    for (size_t j = 0; j < scratch.active.size(); ++j) {
        if (!may_shade(wavefront, hits, j, depth)) continue;
        const int32_t prim = hits.prim[j], material = wavefront.scene.tri_material[prim];
        // the back of a one-sided surface ends the path (make_shading_lanes' test, so its
        // groups have no gaps)
        if (!(scratch.material_two_sided[material] > 0.0f)) {
            const Vec3f wo = -load_vec3(scratch.dir.data() + 3 * scratch.active[j]);
            if (dot(hit_normal(wavefront, hits, j, tn), wo) < 0.0f) {
                if (depth == 0) wavefront.results[scratch.active[j]].depth = hits.t[j];
                continue;
            }
        }
        ++scratch.material_start[material + 1];
        scratch.shade_hits.push_back(static_cast<int32_t>(j));
    }
    for (size_t k = 0; k < nm; ++k) scratch.material_start[k + 1] += scratch.material_start[k];
}

// a / |a| (a zero vector stays zero), N at a time: normalize's operations lane by lane.
PATINA_INLINE V3 normalize_lanes(const V3& a) {
    const F len = sqrt_exact(dot(a, a));
    const B ok = len > F(0.0f);
    return V3{select(ok, a.x / len, a.x), select(ok, a.y / len, a.y), select(ok, a.z / len, a.z)};
}
PATINA_INLINE V3 select3(B m, const V3& a, const V3& b) {
    return V3{select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}

// orthonormal_frame (render/scene.cpp) N at a time, the same operations lane by lane.
PATINA_INLINE void orthonormal_frame_lanes(const V3& n, V3& t, V3& b) {
    const F sign = copysign(F(1.0f), n.z);
    const F a = F(-1.0f) / (sign + n.z), c = n.x * n.y * a;
    t = V3{F(1.0f) + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = V3{c, sign + n.y * n.y * a, -n.y};
}

// The shading points of N hits (scratch.shade_hits[h0, h0 + lanes)) at once: make_shading_point's
// operations lane by lane (interpolated normal and tangent, facing, frame), so every lane
// has the bits the one-hit version gives. Results in lane arrays; ok: false where the path
// ends at the hit (the back of a one-sided surface).
PATINA_INLINE void store_lanes3(float (*dst)[N], const V3& a) {
    store_n<N>(dst[0], a.x);
    store_n<N>(dst[1], a.y);
    store_n<N>(dst[2], a.z);
}

struct PointLanes {
    alignas(64) float p[3][N], ng[3][N], n[3][N], t[3][N], b[3][N], v_local[3][N], eta[N];
    int lane_mask;  // bit k: lane k is a shading point
};

inline void make_shading_lanes(const Wavefront& wavefront, const HitBatch& hits, size_t h0, int lanes,
                               PointLanes& out) {
    const RenderScene& scene = wavefront.scene;
    const PathScratch& scratch = wavefront.scratch;
    // the hits' fields gathered by hit number (the last block's padding repeats its first hit)
    alignas(64) int32_t hit[N];
    if (lanes < N)
        for (int k = 0; k < N; ++k) hit[k] = scratch.shade_hits[h0 + (k < lanes ? k : 0)];
    const I J = load_n<N>(lanes < N ? hit : scratch.shade_hits.data() + h0);
    const I pr = gather(hits.prim, J), material = gather(scene.tri_material, pr);
    // analytic-sphere hits get their geometry from sphere_points; the triangles' gathers read triangle 0 there
    const SphereSet& spheres = scene.tree->spheres;
    const B on_sphere = sphere_lanes<N>(spheres, pr);
    const bool triangles = !all(on_sphere);
    const I pa3 = gather(scratch.active.data(), J) * I(3), pr3 = select(on_sphere, I(0), pr) * I(3);
    const F fu = gather(hits.u, J), fv = gather(hits.v, J), ft = gather(hits.t, J);
    // per material (group_by_material's tables): eta, 1 if dielectric, 1 if either side shades
    const F ein = gather(scratch.material_eta.data(), material);
    const B transmissive = gather(scratch.material_transmissive.data(), material) > F(0.0f);
    const B two_sided = gather(scratch.material_two_sided.data(), material) > F(0.0f);
    const F w0 = F(1.0f) - fu - fv;
    I vert[3];
    for (int c = 0; c < 3; ++c) vert[c] = triangles ? gather(scene.indices, pr3 + I(c)) * I(3) : I(0);
    // a per-vertex attribute interpolated at the hits
    auto interpolate = [&](const float* a) {
        V3 x[3];
        for (int c = 0; c < 3; ++c)
            x[c] = V3{gather(a, vert[c]), gather(a, vert[c] + I(1)), gather(a, vert[c] + I(2))};
        return w0 * x[0] + fu * x[1] + fv * x[2];
    };
    const float* org = scratch.org.data();
    const float* dirs = scratch.dir.data();
    const V3 o{gather(org, pa3), gather(org, pa3 + I(1)), gather(org, pa3 + I(2))};
    const V3 dir{gather(dirs, pa3), gather(dirs, pa3 + I(1)), gather(dirs, pa3 + I(2))};
    const float* tn = scene.tree->normals.data();
    const V3 zero{F(0.0f), F(0.0f), F(0.0f)};
    V3 ng = zero, n = zero, sphere_tangent = zero;
    if (triangles) {
        ng = V3{gather(tn, pr3), gather(tn, pr3 + I(1)), gather(tn, pr3 + I(2))};
        n = normalize_lanes(interpolate(scene.normals));
    }
    V3 p = o + ft * dir;
    if (any(on_sphere)) sphere_points<N>(spheres, on_sphere, pr, o, dir, ft, p, ng, n, sphere_tangent);
    const V3 wo = -dir;
    const B back = dot(ng, wo) < F(0.0f);
    // the geometric normal (from the winding) points out of a closed dielectric
    const F eta = select(transmissive, select(back, F(1.0f) / ein, ein), F(1.0f));
    const B ok = (!back) | two_sided;
    ng = select3(back, -ng, ng);
    // a mesh whose normals point inwards (in front); flipped with ng (behind)
    n = select3(back | (dot(n, ng) < F(0.0f)), -n, n);
    // a shading normal facing away from the viewer (silhouettes of coarse meshes): use the true one
    n = select3(!(dot(n, wo) > F(0.0f)), ng, n);
    V3 ft3, fb3;
    orthonormal_frame_lanes(n, ft3, fb3);
    if (scene.tangents != nullptr || any(on_sphere)) {
        V3 tangent =
            select3(on_sphere, sphere_tangent, triangles && scene.tangents ? interpolate(scene.tangents) : zero);
        tangent = tangent - dot(tangent, n) * n;
        const B has = dot(tangent, tangent) > F(1e-12f);
        const V3 tu = normalize_lanes(tangent);
        ft3 = select3(has, tu, ft3);
        fb3 = select3(has, cross(n, tu), fb3);
    }
    store_lanes3(out.p, p);
    store_lanes3(out.ng, ng);
    store_lanes3(out.n, n);
    store_lanes3(out.t, ft3);
    store_lanes3(out.b, fb3);
    // the view direction in the frame: to_local(sp, -dir)
    store_lanes3(out.v_local, V3{dot(wo, ft3), dot(wo, fb3), dot(wo, n)});
    store_n<N>(out.eta, eta);
    out.lane_mask = movemask(ok) & ((1 << lanes) - 1);
}

// Surface hits become the bounce's shading points in scratch.sorted, grouped by material (groups
// at scratch.material_start), each with its view direction in its frame, its relative index and
// its path's random-number key and sample index; the first hit also fills the AOVs (and, for
// the indirect illuminance, is kept as a sensor: scratch.sensors).
inline void fill_shading_points(const Wavefront& wavefront, const HitBatch& hits, int depth) {
    const RenderScene& scene = wavefront.scene;
    PathScratch& scratch = wavefront.scratch;
    const size_t nm = scene.materials.size();
    const size_t most = scratch.material_start[nm];
    scratch.sorted.resize(most);
    float* vl = grow(scratch.v_local, 3 * most);
    float* eta = grow(scratch.eta, most);
    scratch.point_keys.resize(most);
    scratch.point_index.resize(most);
    float* rows[5] = {grow(scratch.point_lanes.position, 3 * most),
                      grow(scratch.point_lanes.geometric_normal, 3 * most), grow(scratch.point_lanes.tangent, 3 * most),
                      grow(scratch.point_lanes.bitangent, 3 * most), grow(scratch.point_lanes.normal, 3 * most)};
    int32_t* point_path = grow(scratch.point_lanes.path, most);
    std::vector<int32_t>& fill = scratch.next_active;  // reused as the write cursors
    fill.assign(scratch.material_start.begin(), scratch.material_start.end() - 1);
    PointLanes pl;
    for_blocks(scratch.shade_hits.size(), [&](size_t h0, int lanes) {
        make_shading_lanes(wavefront, hits, h0, lanes, pl);
        for (int k = 0; k < lanes; ++k) {
            const int32_t j = scratch.shade_hits[h0 + k];
            const int32_t i = scratch.active[j];
            if (!((pl.lane_mask >> k) & 1)) {
                if (depth == 0) wavefront.results[i].depth = hits.t[j];
                continue;  // the slot is taken by the group's next point
            }
            const int32_t material = scene.tri_material[hits.prim[j]];
            const size_t q = fill[material]++;
            ShadingPoint& sp = scratch.sorted[q];
            sp.path = i;
            sp.material = material;
            sp.p = Vec3f{pl.p[0][k], pl.p[1][k], pl.p[2][k]};
            sp.ng = Vec3f{pl.ng[0][k], pl.ng[1][k], pl.ng[2][k]};
            sp.n = Vec3f{pl.n[0][k], pl.n[1][k], pl.n[2][k]};
            sp.t = Vec3f{pl.t[0][k], pl.t[1][k], pl.t[2][k]};
            sp.b = Vec3f{pl.b[0][k], pl.b[1][k], pl.b[2][k]};
            sp.eta = pl.eta[k];
            if (depth == 0) {
                const Material& mat = scene.materials[material];
                std::copy(mat.albedo, mat.albedo + 3, wavefront.results[i].albedo);
                wavefront.results[i].material = material;
                store_vec3(sp.n, wavefront.results[i].normal);
                wavefront.results[i].depth = hits.t[j];
                if (wavefront.settings.indirect_illuminance) scratch.sensors.push_back(sp);
            }
            const float(*fields[5])[N] = {pl.p, pl.ng, pl.t, pl.b, pl.n};
            for (int f = 0; f < 5; ++f)
                for (int c = 0; c < 3; ++c) rows[f][3 * q + c] = fields[f][c][k];
            point_path[q] = i;
            vl[3 * q] = pl.v_local[0][k];
            vl[3 * q + 1] = pl.v_local[1][k];
            vl[3 * q + 2] = pl.v_local[2][k];
            eta[q] = pl.eta[k];
            scratch.point_keys[q] = static_cast<int32_t>(wavefront.camera_samples[i].key);
            scratch.point_index[q] = static_cast<int32_t>(wavefront.camera_samples[i].index);
        }
    });
    // paths that ended at a hit (the back of a one-sided surface) left their group short:
    // close the gaps, groups in order
    size_t np = 0;
    for (size_t k = 0; k < nm; ++k) {
        const size_t a = scratch.material_start[k], count = fill[k] - a;
        scratch.material_start[k] = np;
        if (a != np) {
            std::copy(scratch.sorted.begin() + a, scratch.sorted.begin() + a + count, scratch.sorted.begin() + np);
            std::copy(vl + 3 * a, vl + 3 * (a + count), vl + 3 * np);
            for (float* r : rows) std::copy(r + 3 * a, r + 3 * (a + count), r + 3 * np);
            std::copy(point_path + a, point_path + a + count, point_path + np);
            std::copy(eta + a, eta + a + count, eta + np);
            std::copy(scratch.point_keys.begin() + a, scratch.point_keys.begin() + a + count,
                      scratch.point_keys.begin() + np);
            std::copy(scratch.point_index.begin() + a, scratch.point_index.begin() + a + count,
                      scratch.point_index.begin() + np);
        }
        np += count;
    }
    scratch.material_start[nm] = np;
    scratch.sorted.resize(np);
    scratch.point_keys.resize(np);
    scratch.point_index.resize(np);
}

// Runs kernel(material, first point, count) for each material's group of sorted points.
template <class Kernel>
inline void for_material_groups(const Wavefront& wavefront, Kernel kernel) {
    for (size_t k = 0; k < wavefront.scene.materials.size(); ++k) {
        const size_t a = wavefront.scratch.material_start[k], count = wavefront.scratch.material_start[k + 1] - a;
        if (count > 0) kernel(wavefront.scene.materials[k], a, count);
    }
}

// The sorted points' buffers a material group's sample, eval and pdf kernels read (the view
// direction in the point's frame, the index it sees) and write (a direction in the frame, the
// BSDF's RGB value there, its density): the BSDF and the light samples both shade through
// them, the written ones grown to the points.
struct MaterialBuffers {
    const float* view_local;  // 3 a point
    const float* eta;
    float* light_local;  // 3 a point: the sampled direction, or the light sample's
    float* bsdf_rgb;     // 3 a point
    float* pdf;

    // the same buffers from sorted point `first` on (a material group's first point)
    MaterialBuffers from(size_t first) const {
        return {view_local + 3 * first, eta + first, light_local + 3 * first, bsdf_rgb + 3 * first, pdf + first};
    }
};

inline MaterialBuffers material_buffers(PathScratch& scratch) {
    const size_t np = scratch.sorted.size();
    return {scratch.v_local.data(), scratch.eta.data(), grow(scratch.l_local, 3 * np), grow(scratch.bsdf_rgb, 3 * np),
            grow(scratch.pdf, np)};
}

// The bounce's surface hits made shading points, grouped by material (group_by_material,
// then fill_shading_points).
inline void make_shading_points(const Wavefront& wavefront, const HitBatch& hits, int depth) {
    PathScratch& scratch = wavefront.scratch;
    group_by_material(wavefront, hits, depth);
    scratch.timer.lap(Stage::GroupMaterial);
    fill_shading_points(wavefront, hits, depth);
    scratch.timer.times.shading_points += scratch.sorted.size();
    scratch.timer.lap(Stage::ShadingPoints);
}

}  // namespace render_detail
PATINA_END_TARGET
