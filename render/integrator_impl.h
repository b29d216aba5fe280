// The wavefront path integrator (see integrator.h), compiled once per width by
// integrator_w{1,4,8}.cpp. A batch of paths advances one bounce at a time through the same
// stages, each over all the paths still alive, as pbrt-v4's wavefront integrator does:
//   trace_bounce                  every path's ray, N per packet
//   add_emission_and_environment  lights hit and rays escaping to the environment or the sun
//   group_by_material             the hits that will be shading points counted by material...
//   make_shading_points           ...and made shading points straight into their material's group,
//                                 so each group is shaded N at a time (and first-hit AOVs)
//   queue_light_samples           one light sample per point (light_sampling_impl.h), MIS-weighted,
//                                 its shadow ray queued
//   sample_bsdf                   the next bounce's direction, throughput, Russian roulette
//   resolve_shadow_rays           the shadow rays traced as packets; the unblocked ones add their light
// Everything random comes from render/sample_numbers.h (Sobol or rng.h's counter-based
// hash, both integer functions of the path's stream and sample), and every kernel it calls gives
// the same bits at every width, so one seed renders the same image at widths 1, 4 and 8
// (the tests check this).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/constants.h"
#include "core/simd/kernel_width.h"
#include "core/vec3.h"
#include "render/cache/cache_stages_impl.h"
#include "render/cache/guided_stages_impl.h"
#include "render/camera.h"
#include "render/env_impl.h"
#include "render/guiding/guide_recording_impl.h"
#include "render/integrator.h"
#include "render/light_sampling_impl.h"
#include "render/material_impl.h"
#include "render/rng.h"
#include "render/sample_numbers.h"
#include "render/scene.h"
#include "render/shadow_rays_impl.h"
#include "render/sphere_points.h"
#include "render/uniforms_impl.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// A world direction in a shading point's frame, and back.
inline Vec3f to_local(const ShadingPoint& sp, const Vec3f& d) { return {dot(d, sp.t), dot(d, sp.b), dot(d, sp.n)}; }
inline Vec3f to_world(const ShadingPoint& sp, const Vec3f& l) { return l.x * sp.t + l.y * sp.b + l.z * sp.n; }

// What every stage of one trace_paths call works on: the scene, the batch's camera samples
// and results, and the paths' state in the scratch arrays -- per path its ray (org, dir),
// throughput, and where and with what density its last BRDF sample left (prev_pos,
// prev_pdf; 0 for a camera ray), which the MIS weights of emission need.
struct Wavefront {
    const RenderScene& s;
    const IntegratorSettings& st;
    const CameraSample* cs;
    PathResult* out;
    PathScratch& sc;
    bool can_sample_lights;  // some light (or the environment) can light something
    bool has_sun;
    float eps;               // secondary rays leave this far off the surface
    // emission the first segment sees counts; not for sensor paths, whose direct light
    // light sampling counts (sensor_illuminance)
    bool first_emission = true;
};

// Path i starts along (o, d) with throughput 1 (its result emptied first by start_paths).
inline void start_path(const Wavefront& w, size_t i, const Vec3f& o, const Vec3f& d) {
    PathScratch& sc = w.sc;
    store_vec3(o, sc.org.data() + 3 * i);
    store_vec3(d, sc.dir.data() + 3 * i);
    std::fill(sc.throughput.data() + 3 * i, sc.throughput.data() + 3 * i + 3, 1.0f);
    sc.prev_pdf[i] = 0;  // a first segment: whatever it sees counts in full
    sc.active.push_back(static_cast<int32_t>(i));
}

// The path arrays sized for n paths, none active yet, the n results empty.
inline void start_paths(const Wavefront& w, size_t n) {
    PathScratch& sc = w.sc;
    grow(sc.org, 3 * n);
    grow(sc.dir, 3 * n);
    grow(sc.throughput, 3 * n);
    grow(sc.prev_pdf, n);
    grow(sc.prev_pos, 3 * n);
    sc.active.clear();
    sc.rays_gathered = false;
    sc.cached.clear();  // none served by the radiance cache (start_camera_paths says otherwise)
    if (sc.cache) cache::cache_state(sc).guides.clear();  // no guides until place_guide_points
    for (size_t i = 0; i < n; ++i) {
        PathResult& r = w.out[i];
        std::fill(r.rgb, r.rgb + 3, 0.0f);
        std::fill(r.albedo, r.albedo + 3, 0.0f);
        std::fill(r.normal, r.normal + 3, 0.0f);
        r.depth = kInfinity;
        r.illuminance = 0;
        r.material = -1;
    }
}

// A pinhole camera's rays through the film positions of samples [0, n), N at a time:
// camera_ray's operations lane by lane (the same bits), from the camera's position.
inline void pinhole_rays(const Camera& c, const CameraSample* cs, size_t n, float* org, float* dir) {
    const float aspect = static_cast<float>(c.width) / static_cast<float>(c.height);
    const V3 right{F(c.right[0]), F(c.right[1]), F(c.right[2])}, up{F(c.up[0]), F(c.up[1]), F(c.up[2])};
    const V3 forward{F(c.forward[0]), F(c.forward[1]), F(c.forward[2])};
    const V3 o{F(c.position[0]), F(c.position[1]), F(c.position[2])};
    for_blocks(n, [&](size_t i, int lanes) {
        alignas(64) float fx[N] = {}, fy[N] = {};
        for (int k = 0; k < lanes; ++k) {
            fx[k] = cs[i + k].fx;
            fy[k] = cs[i + k].fy;
        }
        const F sx = (F(2.0f) * load_n<N>(fx) / F(static_cast<float>(c.width)) - F(1.0f)) * F(c.tan_half_fov) *
                     F(aspect);
        const F sy = (F(1.0f) - F(2.0f) * load_n<N>(fy) / F(static_cast<float>(c.height))) * F(c.tan_half_fov);
        const V3 d = forward + sx * right + sy * up;
        const F inv = F(1.0f) / sqrt_exact(dot(d, d));
        store_rows(org, i, lanes, o);
        store_rows(dir, i, lanes, inv * d);
    });
}

// The batch's camera rays, with throughput 1 and empty results; every path active.
inline void start_camera_paths(const Wavefront& w, size_t n) {
    start_paths(w, n);
    const bool lens = w.s.camera.aperture_radius > 0;  // a pinhole draws no lens numbers
    if (!lens) {  // start_path for every path, the rays N at a time
        PathScratch& sc = w.sc;
        pinhole_rays(w.s.camera, w.cs, n, sc.org.data(), sc.dir.data());
        std::fill(sc.throughput.data(), sc.throughput.data() + 3 * n, 1.0f);
        std::fill(sc.prev_pdf.data(), sc.prev_pdf.data() + n, 0.0f);
        sc.active.resize(n);
        for (size_t i = 0; i < n; ++i) sc.active[i] = static_cast<int32_t>(i);
        if (w.st.mode == IntegratorMode::Cache) sc.cached.assign(n, 0);
        return;
    }
    for (size_t i = 0; i < n; ++i) {
        const CameraSample& c = w.cs[i];
        const float lu = lens ? sample_uniform(w.st.sampler, c.key, c.index, 0, kDimLensU) : 0.0f;
        const float lv = lens ? sample_uniform(w.st.sampler, c.key, c.index, 0, kDimLensV) : 0.0f;
        Vec3f o, d;
        camera_ray(w.s.camera, c.fx, c.fy, lu, lv, o, d);
        start_path(w, i, o, d);
    }
    if (w.st.mode == IntegratorMode::Cache) w.sc.cached.assign(n, 0);
}

// Paths along given rays (the radiance cache's: n origins and directions, row by row).
inline void start_given_paths(const Wavefront& w, const float* org, const float* dir, size_t n) {
    start_paths(w, n);
    for (size_t i = 0; i < n; ++i) start_path(w, i, load_vec3(org + 3 * i), load_vec3(dir + 3 * i));
}

// 1. The active paths' rays, N per packet; hit j belongs to path sc.active[j].
inline HitBatch trace_bounce(const Wavefront& w, int depth) {
    PathScratch& sc = w.sc;
    const size_t m = sc.active.size();
    float* ro = grow(sc.ray_org, 3 * m);
    float* rd = grow(sc.ray_dir, 3 * m);
    if (!sc.rays_gathered)  // (update_paths wrote the next bounce's rays in order already)
        for (size_t j = 0; j < m; ++j) {
            const int32_t i = sc.active[j];
            std::copy(sc.org.data() + 3 * i, sc.org.data() + 3 * i + 3, ro + 3 * j);
            std::copy(sc.dir.data() + 3 * i, sc.dir.data() + 3 * i + 3, rd + 3 * j);
        }
    HitBatch hits{grow(sc.hit_t, m), grow(sc.hit_prim, m), grow(sc.hit_u, m), grow(sc.hit_v, m)};
    sc.timer.lap(Stage::RayGather);
    const RayBatch rays{ro, rd, 0.0f, nullptr, kInfinity};
    // camera rays are coherent: kd-tree packets; the rest one at a time through the BVH
    if (depth > 0 && w.s.bvh) trace_kernels().intersect_bvh(*w.s.bvh, rays, hits, 0, m);
    else trace_kernels().intersect(*w.s.tree, rays, hits, 0, m);
    sc.rays_traced += m;
    (depth == 0 ? sc.timer.times.camera_rays : sc.timer.times.secondary_rays) += m;
    sc.timer.lap(depth == 0 ? Stage::TraceCamera : Stage::TraceSecondary);
    return hits;
}

// Misses see the environment, N directions at a time: its radiance and (for MIS after a
// BRDF sample: depth > 0) the density of light sampling; and the sun's disc, where they go
// through it.
inline void add_environment(const Wavefront& w, int depth) {
    const RenderScene& s = w.s;
    PathScratch& sc = w.sc;
    const size_t n = sc.misses.size();
    if (n == 0) return;
    const float* thr = sc.throughput.data();
    const float* prev_pdf = sc.prev_pdf.data();
    float* d = grow(sc.miss_dir, 3 * n);
    float* le = grow(sc.miss_rgb, 3 * n);
    float* lp = grow(sc.miss_pdf, n);
    for (size_t j = 0; j < n; ++j)
        std::copy(sc.dir.data() + 3 * sc.misses[j], sc.dir.data() + 3 * sc.misses[j] + 3, d + 3 * j);
    // a path's first segment (prev_pdf 0: start_path) is not weighed against light sampling
    const bool with_pdf = depth > 0 && w.can_sample_lights;
    if (s.env.present) for_blocks(n, [&](size_t i, int lanes) {
        F r, g, b;
        const F p = env_w::radiance_and_pdf(s.env, load_rows(d, i, lanes), with_pdf, r, g, b);
        store_rows(le, i, lanes, r, g, b);
        store_lanes(lp, i, lanes, p);
    });
    const int env_light = static_cast<int>(s.lights.size());
    // without local lights (or with the environment alone) the selection does not depend on
    // the point: the environment's probability computed once (the same operations as per point)
    const bool local = selection_is_local(s);
    const float env_selection = s.env.present && !local ? selection_probability(s, Vec3f{0, 0, 0}, env_light) : 0.0f;
    for (size_t j = 0; j < n; ++j) {
        const int32_t i = sc.misses[j];
        const Vec3f from = load_vec3(sc.prev_pos.data() + 3 * i);
        const bool mis = prev_pdf[i] > 0 && w.can_sample_lights;  // after a BRDF sample (not a camera ray)
        if (s.env.present) {
            const float wt = mis ? power_heuristic(prev_pdf[i], (local ? selection_probability(s, from, env_light)
                                                                       : env_selection) * lp[j])
                                 : 1.0f;
            for (int k = 0; k < 3; ++k) w.out[i].rgb[k] += thr[3 * i + k] * le[3 * j + k] * wt;
        }
        for (size_t li = 0; li < s.lights.size(); ++li) {
            const Light& l = s.lights[li];
            if (l.kind != LightKind::Sun || !(dot(load_vec3(d + 3 * j), load_vec3(l.direction)) >= l.cos_sun)) continue;
            const float wt = mis ? power_heuristic(prev_pdf[i], selection_probability(s, from, int(li)) /
                                                                    (2.0f * kPi * l.sun_one_minus_cos))
                                 : 1.0f;
            for (int k = 0; k < 3; ++k) w.out[i].rgb[k] += thr[3 * i + k] * l.power[k] * wt;
        }
    }
}

// 2. Emission seen: an area light hit (MIS-weighted after a BRDF sample) adds its radiance;
//    a miss sees the environment and the sun.
inline void add_emission_and_environment(const Wavefront& w, const HitBatch& hits, int depth) {
    const RenderScene& s = w.s;
    PathScratch& sc = w.sc;
    sc.misses.clear();
    const bool emission = depth > 0 || w.first_emission;
    for (size_t j = 0; j < sc.active.size(); ++j) {
        const int32_t i = sc.active[j];
        const int32_t prim = hits.prim[j];
        if (prim < 0) {
            if (emission && (s.env.present || w.has_sun)) sc.misses.push_back(i);
            continue;
        }
        const Material& mat = s.materials[s.tri_material[prim]];
        if (mat.kind != MaterialKind::Emitter) continue;
        const Light& l = s.lights[mat.light];
        const Vec3f ng = load_vec3(s.tree->normals.data() + 3 * static_cast<size_t>(prim));  // quads: their normal
        const float facing = -dot(load_vec3(sc.dir.data() + 3 * i), ng);
        if (emission && (facing > 0 || (l.two_sided && facing < 0))) {
            float wt = 1.0f;
            if (sc.prev_pdf[i] > 0 && w.can_sample_lights)
                wt = power_heuristic(sc.prev_pdf[i], area_light_pdf(s, load_vec3(sc.prev_pos.data() + 3 * i),
                                                                    mat.light, facing, hits.t[j]));
            const float* T = sc.throughput.data() + 3 * i;
            for (int k = 0; k < 3; ++k) w.out[i].rgb[k] += T[k] * l.power[k] * wt;
        }
        if (depth == 0) w.out[i].depth = hits.t[j];
    }
    add_environment(w, depth);
}

// Whether hit j may become a shading point: a surface (not a light) while the path may
// still bounce (make_shading_point may still end the path there).
inline bool may_shade(const Wavefront& w, const HitBatch& hits, size_t j, int depth) {
    const int32_t prim = hits.prim[j];
    // (a path whose first hit's indirect light the cache gave only looks for emission)
    const bool cached = depth > 0 && !w.sc.cached.empty() && w.sc.cached[w.sc.active[j]];
    return prim >= 0 && w.s.materials[w.s.tri_material[prim]].kind != MaterialKind::Emitter &&
           depth < w.st.max_depth && !cached;
}

// Hit j's geometric normal (from the winding; an analytic sphere's outwards), as
// make_shading_lanes has it before facing the viewer.
inline Vec3f hit_normal(const Wavefront& w, const HitBatch& hits, size_t j, const float* tn) {
    const int32_t prim = hits.prim[j];
    const SphereSet& spheres = w.s.tree->spheres;
    if (!spheres.owns(prim)) return load_vec3(tn + 3 * static_cast<size_t>(prim));
    const int32_t i = w.sc.active[j];
    return sphere_normal<1>(spheres, prim - spheres.prim_base, load_vec3(w.sc.org.data() + 3 * i),
                            load_vec3(w.sc.dir.data() + 3 * i), hits.t[j]);
}

// 3. Grouping by material before the points exist: the hits that become shading points
//    (not the back of a one-sided surface, where the path ends) in sc.shade_hits, counted
//    per material (sc.material_start: each group's first slot in sc.sorted), so
//    make_shading_points writes each point straight into its group, in hit order (what a
//    stable counting sort of the points would give, without building and copying them twice).
inline void group_by_material(const Wavefront& w, const HitBatch& hits, int depth) {
    PathScratch& sc = w.sc;
    const size_t nm = w.s.materials.size();
    sc.material_start.assign(nm + 1, 0);
    sc.material_eta.resize(nm);
    sc.material_transmissive.resize(nm);
    sc.material_two_sided.resize(nm);
    for (size_t k = 0; k < nm; ++k) {
        const Material& m = w.s.materials[k];
        const bool transmissive = m.kind == MaterialKind::Dielectric;
        sc.material_eta[k] = transmissive ? m.eta[0] : 1.0f;
        sc.material_transmissive[k] = transmissive ? 1.0f : 0.0f;
        sc.material_two_sided[k] = m.two_sided || transmissive ? 1.0f : 0.0f;
    }
    sc.shade_hits.clear();
    const float* tn = w.s.tree->normals.data();
    for (size_t j = 0; j < sc.active.size(); ++j) {
        if (!may_shade(w, hits, j, depth)) continue;
        const int32_t prim = hits.prim[j], material = w.s.tri_material[prim];
        // the back of a one-sided surface ends the path (make_shading_lanes' test, so its
        // groups have no gaps)
        if (!(sc.material_two_sided[material] > 0.0f)) {
            const Vec3f wo = -load_vec3(sc.dir.data() + 3 * sc.active[j]);
            if (dot(hit_normal(w, hits, j, tn), wo) < 0.0f) {
                if (depth == 0) w.out[sc.active[j]].depth = hits.t[j];
                continue;
            }
        }
        ++sc.material_start[material + 1];
        sc.shade_hits.push_back(static_cast<int32_t>(j));
    }
    for (size_t k = 0; k < nm; ++k) sc.material_start[k + 1] += sc.material_start[k];
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

// The shading points of N hits (sc.shade_hits[h0, h0 + lanes)) at once: make_shading_point's
// operations lane by lane (interpolated normal and tangent, facing, frame), so every lane
// has the bits the one-hit version gives. Results in lane arrays; ok: false where the path
// ends at the hit (the back of a one-sided surface).
PATINA_INLINE void store_lanes3(float (*dst)[N], const V3& a) {
    store_n<N>(dst[0], a.x);
    store_n<N>(dst[1], a.y);
    store_n<N>(dst[2], a.z);
}

struct PointLanes {
    alignas(64) float p[3][N], ng[3][N], n[3][N], t[3][N], b[3][N], vl[3][N], eta[N];
    int ok;  // bit k: lane k is a shading point
};

inline void make_shading_lanes(const Wavefront& w, const HitBatch& hits, size_t h0, int lanes, PointLanes& out) {
    const RenderScene& s = w.s;
    const PathScratch& sc = w.sc;
    // the hits' fields gathered by hit number (the last block's padding repeats its first hit)
    alignas(64) int32_t hit[N];
    if (lanes < N)
        for (int k = 0; k < N; ++k) hit[k] = sc.shade_hits[h0 + (k < lanes ? k : 0)];
    const I J = load_n<N>(lanes < N ? hit : sc.shade_hits.data() + h0);
    const I pr = gather(hits.prim, J), material = gather(s.tri_material, pr);
    // analytic-sphere hits get their geometry from sphere_points; the triangles' gathers read triangle 0 there
    const SphereSet& spheres = s.tree->spheres;
    const B on_sphere = sphere_lanes<N>(spheres, pr);
    const bool triangles = !all(on_sphere);
    const I pa3 = gather(sc.active.data(), J) * I(3), pr3 = select(on_sphere, I(0), pr) * I(3);
    const F fu = gather(hits.u, J), fv = gather(hits.v, J), ft = gather(hits.t, J);
    // per material (group_by_material's tables): eta, 1 if dielectric, 1 if either side shades
    const F ein = gather(sc.material_eta.data(), material);
    const B transmissive = gather(sc.material_transmissive.data(), material) > F(0.0f);
    const B two_sided = gather(sc.material_two_sided.data(), material) > F(0.0f);
    const F w0 = F(1.0f) - fu - fv;
    I vert[3];
    for (int c = 0; c < 3; ++c) vert[c] = triangles ? gather(s.indices, pr3 + I(c)) * I(3) : I(0);
    // a per-vertex attribute interpolated at the hits
    auto interpolate = [&](const float* a) {
        V3 x[3];
        for (int c = 0; c < 3; ++c)
            x[c] = V3{gather(a, vert[c]), gather(a, vert[c] + I(1)), gather(a, vert[c] + I(2))};
        return w0 * x[0] + fu * x[1] + fv * x[2];
    };
    const float* org = sc.org.data();
    const float* dirs = sc.dir.data();
    const V3 o{gather(org, pa3), gather(org, pa3 + I(1)), gather(org, pa3 + I(2))};
    const V3 dir{gather(dirs, pa3), gather(dirs, pa3 + I(1)), gather(dirs, pa3 + I(2))};
    const float* tn = s.tree->normals.data();
    const V3 zero{F(0.0f), F(0.0f), F(0.0f)};
    V3 ng = zero, n = zero, sphere_tangent = zero;
    if (triangles) {
        ng = V3{gather(tn, pr3), gather(tn, pr3 + I(1)), gather(tn, pr3 + I(2))};
        n = normalize_lanes(interpolate(s.normals));
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
    if (s.tangents != nullptr || any(on_sphere)) {
        V3 tangent = select3(on_sphere, sphere_tangent, triangles && s.tangents ? interpolate(s.tangents) : zero);
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
    store_lanes3(out.vl, V3{dot(wo, ft3), dot(wo, fb3), dot(wo, n)});
    store_n<N>(out.eta, eta);
    out.ok = movemask(ok) & ((1 << lanes) - 1);
}

// 4. Surface hits become the bounce's shading points in sc.sorted, grouped by material (groups
//    at sc.material_start), each with its view direction in its frame, its relative index and
//    its path's random-number key and sample index; the first hit also fills the AOVs (and, for
//    the indirect illuminance, is kept as a sensor: sc.sensors).
inline void make_shading_points(const Wavefront& w, const HitBatch& hits, int depth) {
    const RenderScene& s = w.s;
    PathScratch& sc = w.sc;
    const size_t nm = s.materials.size();
    const size_t most = sc.material_start[nm];
    sc.sorted.resize(most);
    float* vl = grow(sc.v_local, 3 * most);
    float* eta = grow(sc.eta, most);
    sc.point_keys.resize(most);
    sc.point_index.resize(most);
    float* rows[5] = {grow(sc.pt_p, 3 * most), grow(sc.pt_ng, 3 * most), grow(sc.pt_t, 3 * most),
                      grow(sc.pt_b, 3 * most), grow(sc.pt_n, 3 * most)};
    int32_t* pt_path = grow(sc.pt_path, most);
    std::vector<int32_t>& fill = sc.next_active;  // reused as the write cursors
    fill.assign(sc.material_start.begin(), sc.material_start.end() - 1);
    PointLanes pl;
    for_blocks(sc.shade_hits.size(), [&](size_t h0, int lanes) {
        make_shading_lanes(w, hits, h0, lanes, pl);
        for (int k = 0; k < lanes; ++k) {
            const int32_t j = sc.shade_hits[h0 + k];
            const int32_t i = sc.active[j];
            if (!((pl.ok >> k) & 1)) {
                if (depth == 0) w.out[i].depth = hits.t[j];
                continue;  // the slot is taken by the group's next point
            }
            const int32_t material = s.tri_material[hits.prim[j]];
            const size_t q = fill[material]++;
            ShadingPoint& sp = sc.sorted[q];
            sp.path = i;
            sp.material = material;
            sp.p = Vec3f{pl.p[0][k], pl.p[1][k], pl.p[2][k]};
            sp.ng = Vec3f{pl.ng[0][k], pl.ng[1][k], pl.ng[2][k]};
            sp.n = Vec3f{pl.n[0][k], pl.n[1][k], pl.n[2][k]};
            sp.t = Vec3f{pl.t[0][k], pl.t[1][k], pl.t[2][k]};
            sp.b = Vec3f{pl.b[0][k], pl.b[1][k], pl.b[2][k]};
            sp.eta = pl.eta[k];
            if (depth == 0) {
                const Material& mat = s.materials[material];
                std::copy(mat.albedo, mat.albedo + 3, w.out[i].albedo);
                w.out[i].material = material;
                store_vec3(sp.n, w.out[i].normal);
                w.out[i].depth = hits.t[j];
                if (w.st.indirect_illuminance) sc.sensors.push_back(sp);
            }
            const float(*fields[5])[N] = {pl.p, pl.ng, pl.t, pl.b, pl.n};
            for (int f = 0; f < 5; ++f)
                for (int c = 0; c < 3; ++c) rows[f][3 * q + c] = fields[f][c][k];
            pt_path[q] = i;
            vl[3 * q] = pl.vl[0][k];
            vl[3 * q + 1] = pl.vl[1][k];
            vl[3 * q + 2] = pl.vl[2][k];
            eta[q] = pl.eta[k];
            sc.point_keys[q] = static_cast<int32_t>(w.cs[i].key);
            sc.point_index[q] = static_cast<int32_t>(w.cs[i].index);
        }
    });
    // paths that ended at a hit (the back of a one-sided surface) left their group short:
    // close the gaps, groups in order
    size_t np = 0;
    for (size_t k = 0; k < nm; ++k) {
        const size_t a = sc.material_start[k], count = fill[k] - a;
        sc.material_start[k] = np;
        if (a != np) {
            std::copy(sc.sorted.begin() + a, sc.sorted.begin() + a + count, sc.sorted.begin() + np);
            std::copy(vl + 3 * a, vl + 3 * (a + count), vl + 3 * np);
            for (float* r : rows) std::copy(r + 3 * a, r + 3 * (a + count), r + 3 * np);
            std::copy(pt_path + a, pt_path + a + count, pt_path + np);
            std::copy(eta + a, eta + a + count, eta + np);
            std::copy(sc.point_keys.begin() + a, sc.point_keys.begin() + a + count, sc.point_keys.begin() + np);
            std::copy(sc.point_index.begin() + a, sc.point_index.begin() + a + count, sc.point_index.begin() + np);
        }
        np += count;
    }
    sc.material_start[nm] = np;
    sc.sorted.resize(np);
    sc.point_keys.resize(np);
    sc.point_index.resize(np);
}

// Runs kernel(material, first point, count) for each material's group of sorted points.
template <class Kernel>
inline void for_material_groups(const Wavefront& w, Kernel kernel) {
    for (size_t k = 0; k < w.s.materials.size(); ++k) {
        const size_t a = w.sc.material_start[k], count = w.sc.material_start[k + 1] - a;
        if (count > 0) kernel(w.s.materials[k], a, count);
    }
}

// Veach's power heuristic (power_heuristic) N at a time, the same operations lane by lane.
PATINA_INLINE F power_heuristic_lanes(F a, F b) {
    const F r = b / a;
    return select(!(a > F(0.0f)), F(0.0f), select(!(b > F(0.0f)), F(1.0f), F(1.0f) / (F(1.0f) + r * r)));
}

// std::max and std::min lane by lane (the second argument where the first does not compare:
// the scalar code's NaN behaviour too).
PATINA_INLINE F std_max(F a, F b) { return select(a < b, b, a); }
PATINA_INLINE F std_min(F a, F b) { return select(b < a, b, a); }

// The lanes whose bit is set in `bits`, as a mask.
PATINA_INLINE B mask_of_bits(int bits) {
    constexpr int32_t kBit[16] = {1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384, 32768};
    const I bit = load_n<N>(kBit);
    return (I(bits) & bit) == bit;
}

// N path numbers from an (n,) array, the last block's padding lanes path 0 (read, never written).
PATINA_INLINE I load_path_lanes(const int32_t* p, size_t i, int lanes) {
    if (lanes == N) return load_n<N>(p + i);
    alignas(64) int32_t pad[N] = {};
    std::copy(p + i, p + i + lanes, pad);
    return load_n<N>(pad);
}

// The light samples' shadow rays, N points at a time: each lane's contribution (throughput x
// BRDF x cosine x radiance x MIS weight / pdf), lux and ray with queue_shadow_ray's operations,
// and the lanes that carry light written to the queue in point order (a compress-store).
inline void queue_shadow_lanes(const Wavefront& w, int depth, size_t np) {
    PathScratch& sc = w.sc;
    const float* ll = sc.l_local.data();
    const float* fv = sc.f.data();
    const float* pdf = sc.pdf.data();
    resize_shadow_rays(sc, np);
    size_t m = 0;
    for_blocks(np, [&](size_t q0, int lanes) {
        int ok_bits = 0, delta_bits = 0;
        for (int k = 0; k < lanes; ++k) {
            ok_bits |= (sc.ls_ok[q0 + k] ? 1 : 0) << k;
            delta_bits |= (sc.ls_delta[q0 + k] ? 1 : 0) << k;
        }
        if (ok_bits == 0) return;
        const V3 L = load_rows(ll, q0, lanes), FV = load_rows(fv, q0, lanes), RGB = load_rows(sc.ls_rgb.data(), q0, lanes);
        const F z = L.z, lp = load_lanes(sc.ls_pdf.data(), q0, lanes), cos_l = abs(z);
        const I path3 = load_path_lanes(sc.pt_path.data(), q0, lanes) * I(3);
        const float* thr = sc.throughput.data();
        const F wt = select(mask_of_bits(delta_bits), F(1.0f), power_heuristic_lanes(lp, load_lanes(pdf, q0, lanes)));
        const F c[3] = {gather(thr, path3) * FV.x * cos_l * RGB.x * wt / lp,
                        gather(thr, path3 + I(1)) * FV.y * cos_l * RGB.y * wt / lp,
                        gather(thr, path3 + I(2)) * FV.z * cos_l * RGB.z * wt / lp};
        const B front = z > F(0.0f);
        const F lum = F(0.2126f) * RGB.x + F(0.7152f) * RGB.y + F(0.0722f) * RGB.z;
        const F lux = depth == 0 ? select(front, F(kLumensPerWatt) * lum * cos_l / lp, F(0.0f)) : F(0.0f);
        const F side = select(front, F(w.eps), F(-w.eps));
        const B none_carried = (c[0] <= F(0.0f)) & (c[1] <= F(0.0f)) & (c[2] <= F(0.0f)) & (lux <= F(0.0f));
        const B queued = (cos_l > F(0.0f)) & !none_carried;
        // queue_shadow_ray: from the lifted origin, aimed at the light's point unless at infinity
        const V3 P = load_rows(sc.pt_p.data(), q0, lanes), D = load_rows(sc.ls_dir.data(), q0, lanes);
        const F ds = load_lanes(sc.ls_dist.data(), q0, lanes);
        const V3 o = P + side * load_rows(sc.pt_ng.data(), q0, lanes);
        const V3 to = P + ds * D - o;
        const F len = sqrt_exact(dot(to, to));
        const B finite = !(abs(ds) == F(kInfinity));
        const V3 d = select3(finite, V3{to.x / len, to.y / len, to.z / len}, D);
        const F tmax = select(finite, len * F(1.0f - 1e-4f), F(kInfinity));
        alignas(64) float oo[3][N], dd[3][N], cc[3][N], tt[N], lx[N];
        for (int k = 0; k < 3; ++k) {
            store_n<N>(cc[k], c[k]);
        }
        store_lanes3(oo, o);
        store_lanes3(dd, d);
        store_n<N>(tt, tmax);
        store_n<N>(lx, lux);
        for (int bits = movemask(queued) & ok_bits; bits; bits &= bits - 1) {
            const int k = __builtin_ctz(static_cast<unsigned>(bits));
            sc.shadow_path[m] = sc.pt_path[q0 + k];
            for (int a = 0; a < 3; ++a) {
                sc.shadow_org[3 * m + a] = oo[a][k];
                sc.shadow_dir[3 * m + a] = dd[a][k];
                sc.shadow_rgb[3 * m + a] = cc[a][k];
            }
            sc.shadow_tmax[m] = tt[k];
            sc.shadow_lux[m] = lx[k];
            ++m;
        }
    });
    resize_shadow_rays(sc, m);
}

// 5. Light sampling: one light sample per point; the BRDF evaluated for it (N points of a
//    material at a time), its MIS weight against BRDF sampling, and its shadow ray queued
//    with what it adds if unblocked (and, at the first hit, the illuminance AOV).
inline void queue_light_samples(const Wavefront& w, int depth) {
    PathScratch& sc = w.sc;
    clear_shadow_rays(sc);
    if (!w.can_sample_lights) return;
    const size_t np = sc.sorted.size();
    const float* vl = sc.v_local.data();
    const float* eta = sc.eta.data();
    float* ll = grow(sc.l_local, 3 * np);
    float* fv = grow(sc.f, 3 * np);
    float* pdf = grow(sc.pdf, np);
    sample_lights(w.s, sc, depth, np);
    for (size_t q = 0; q < np; ++q) {
        const ShadingPoint& sp = sc.sorted[q];
        const Vec3f ldir = load_vec3(sc.ls_dir.data() + 3 * q);
        const Vec3f l = sc.ls_ok[q] ? to_local(sp, ldir) : Vec3f{0, 0, 0};
        store_vec3(l, ll + 3 * q);
        // the light must be on the side the local direction says (shading normals bend)
        const float side = dot(ldir, sp.ng);
        const bool transmissive = w.s.materials[sp.material].kind == MaterialKind::Dielectric;
        sc.ls_ok[q] = sc.ls_ok[q] && (transmissive ? side * l.z > 0 : side > 0);
    }
    sc.timer.lap(Stage::LightToLocal);
    for_material_groups(w, [&](const Material& m, size_t a, size_t count) {
        material_eval(m, ll + 3 * a, vl + 3 * a, eta + a, fv + 3 * a, count);
        material_pdf(m, ll + 3 * a, vl + 3 * a, eta + a, pdf + a, count);
    });
    if (w.st.mode == IntegratorMode::CacheGuided) cache::mix_light_pdfs(sc, w.st.cache, ll, pdf, np);
    sc.timer.lap(Stage::ShadeLight);
    queue_shadow_lanes(w, depth, np);
    sc.timer.lap(Stage::ShadowQueue);
}

// The paths after their BRDF samples, N points at a time, each lane with the one-point
// operations: the direction into the world (on the side the local direction says), the
// throughput times BRDF x cosine / pdf, Russian roulette, and the next ray of the paths that
// go on, appended to sc.next_active in point order.
inline void update_paths(const Wavefront& w, int depth, size_t np) {
    PathScratch& sc = w.sc;
    const float* ll = sc.l_local.data();
    const float* fv = sc.f.data();
    const float* pdf = sc.pdf.data();
    const bool roulette = depth + 1 >= w.st.rr_depth;
    sc.next_active.resize(np);
    float* next_org = grow(sc.next_ray_org, 3 * np);
    float* next_dir = grow(sc.next_ray_dir, 3 * np);
    size_t m = 0;
    for_blocks(np, [&](size_t q0, int lanes) {
        const I path = load_path_lanes(sc.pt_path.data(), q0, lanes), path3 = path * I(3);
        alignas(64) int32_t key[N] = {}, index[N] = {};
        uint32_t all = 0;
        if (roulette)
            for (int k = 0; k < lanes; ++k) {
                const CameraSample& c = w.cs[sc.pt_path[q0 + k]];
                key[k] = static_cast<int32_t>(c.key);
                index[k] = static_cast<int32_t>(c.index);
                all |= c.index;
            }
        const V3 L = load_rows(ll, q0, lanes);
        const F P = load_lanes(pdf, q0, lanes);
        B go = (P > F(0.0f)) & (L.z != F(0.0f));
        // to_world(sp, l), normalised
        const V3 wl = normalize_lanes(L.x * load_rows(sc.pt_t.data(), q0, lanes) +
                                      L.y * load_rows(sc.pt_b.data(), q0, lanes) +
                                      L.z * load_rows(sc.pt_n.data(), q0, lanes));
        const V3 NG = load_rows(sc.pt_ng.data(), q0, lanes);
        const V3 FV = load_rows(fv, q0, lanes);
        go = go & (dot(wl, NG) * L.z > F(0.0f));  // the side the local direction says
        const float* thr = sc.throughput.data();
        F T[3] = {gather(thr, path3) * (FV.x * abs(L.z) / P), gather(thr, path3 + I(1)) * (FV.y * abs(L.z) / P),
                  gather(thr, path3 + I(2)) * (FV.z * abs(L.z) / P)};
        // the throughput as the path left it (a path that ends below keeps the product)
        const int updated = movemask(go) & ((1 << lanes) - 1);
        go = go & ((T[0] > F(0.0f)) | (T[1] > F(0.0f)) | (T[2] > F(0.0f)));
        if (roulette) {
            const F survive = std_min(F(0.95f), std_max(T[0], std_max(T[1], T[2])));
            const F u = sample_uniform_lanes(w.st.sampler, load_n<N>(key), load_n<N>(index), bit_length(all), depth,
                                             kDimRoulette);
            const B lives = go & !(u >= survive);
            for (int c = 0; c < 3; ++c) T[c] = select(lives, T[c] / survive, T[c]);
            go = lives;
        }
        const F side = select(L.z > F(0.0f), F(w.eps), F(-w.eps));
        const V3 Pp = load_rows(sc.pt_p.data(), q0, lanes);
        const V3 o = Pp + side * NG;
        alignas(64) float tt[3][N], oo[3][N], dd[3][N], pp[3][N];
        for (int c = 0; c < 3; ++c) store_n<N>(tt[c], T[c]);
        store_lanes3(pp, Pp);
        store_lanes3(oo, o);
        store_lanes3(dd, wl);
        for (int bits = updated; bits; bits &= bits - 1) {
            const int k = __builtin_ctz(static_cast<unsigned>(bits));
            float* Tk = sc.throughput.data() + 3 * sc.pt_path[q0 + k];
            for (int c = 0; c < 3; ++c) Tk[c] = tt[c][k];
        }
        for (int bits = movemask(go) & ((1 << lanes) - 1); bits; bits &= bits - 1) {
            const int k = __builtin_ctz(static_cast<unsigned>(bits));
            const size_t q = q0 + k;
            const int32_t i = sc.pt_path[q];
            for (int c = 0; c < 3; ++c) {
                sc.org[3 * i + c] = next_org[3 * m + c] = oo[c][k];
                sc.dir[3 * i + c] = next_dir[3 * m + c] = dd[c][k];
                sc.prev_pos[3 * i + c] = pp[c][k];
            }
            sc.prev_pdf[i] = pdf[q];
            sc.next_active[m++] = i;
        }
    });
    sc.next_active.resize(m);
}

// 6. BRDF sampling: each point's next direction (N points of a material at a time); the
//    path's throughput, Russian roulette, and the next bounce's ray for the survivors
//    (sc.next_active).
inline void sample_bsdf(const Wavefront& w, int depth) {
    PathScratch& sc = w.sc;
    const size_t np = sc.sorted.size();
    const float* vl = sc.v_local.data();
    const float* eta = sc.eta.data();
    float* ll = grow(sc.l_local, 3 * np);
    float* fv = grow(sc.f, 3 * np);
    float* pdf = grow(sc.pdf, np);
    float* upick = grow(sc.u_pick, np);
    float* u1 = grow(sc.u1, np);
    float* u2 = grow(sc.u2, np);
    const bool guided = w.st.mode == IntegratorMode::CacheGuided && cache::guided_here(sc);
    // the pick only for the groups whose sampling reads it (and the guide's, which picks too)
    if (guided) fill_uniforms(sc, np, depth, kDimBsdfPick, upick);
    else for_material_groups(w, [&](const Material& m, size_t a, size_t count) {
        if (sampling_picks(m)) fill_uniforms(sc, a, count, depth, kDimBsdfPick, upick);
    });
    fill_uniforms(sc, np, depth, kDimBsdfU, u1);
    fill_uniforms(sc, np, depth, kDimBsdfV, u2);
    sc.timer.lap(Stage::BsdfUniforms);
    if (guided) cache::guided_picks(w);
    for_material_groups(w, [&](const Material& m, size_t a, size_t count) {
        material_sample(m, vl + 3 * a, eta + a, upick + a, u1 + a, u2 + a, ll + 3 * a, pdf + a, count);
        material_eval(m, ll + 3 * a, vl + 3 * a, eta + a, fv + 3 * a, count);
    });
    if (guided) cache::guided_directions(w);
    sc.timer.lap(Stage::ShadeSample);
    sc.next_active.clear();
    if (depth + 1 <= w.st.max_depth) update_paths(w, depth, np);
    sc.timer.lap(Stage::PathUpdate);
}

// 7. The queued shadow rays, N per packet; the unblocked ones add their light.
inline void resolve_shadow_rays(const Wavefront& w) {
    PathScratch& sc = w.sc;
    const uint8_t* blocked = trace_shadow_rays(w.s, sc);
    sc.timer.times.shadow_rays += sc.shadow_path.size();
    sc.timer.lap(Stage::TraceShadow);
    for (size_t q = 0; q < sc.shadow_path.size(); ++q) {
        if (blocked[q]) continue;
        PathResult& r = w.out[sc.shadow_path[q]];
        for (int k = 0; k < 3; ++k) r.rgb[k] += sc.shadow_rgb[3 * q + k];
        r.illuminance += sc.shadow_lux[q];
    }
    sc.timer.lap(Stage::ShadowResolve);
}

// The radiance cache's rays (origins, directions, stream keys and indices; n of them)
// traced by the path tracer with `st` (mode path), leaving out the emission they see
// directly: out[i].rgb is the indirect radiance arriving along ray i, depth and normal
// what it hit first.
void trace_given_rays(const RenderScene& s, const IntegratorSettings& st, const float* org, const float* dir,
                      const uint32_t* keys, const uint32_t* indices, size_t n, PathResult* out, PathScratch& sc,
                      std::vector<CameraSample>& samples);

// At the first hit, the radiance cache's stage of the cache integrators (render/cache/).
// The settings of the cache's own rays, which start at the first hit: one bounce fewer,
// roulette one sooner.
inline IntegratorSettings cache_ray_settings(const IntegratorSettings& st) {
    IntegratorSettings inner = st;
    inner.mode = IntegratorMode::Path;
    inner.indirect_illuminance = false;
    inner.max_depth = st.max_depth - 1;
    inner.rr_depth = std::max(1, st.rr_depth - 1);
    // a guide needs the shape of the indirect light, not its value: the direct light at the
    // hits (one bounce) is that shape at a fraction of the full paths' cost
    if (st.mode == IntegratorMode::CacheGuided) inner.max_depth = 1;
    return inner;
}

inline void run_cache_stage(const Wavefront& w) {
    const IntegratorSettings inner = cache_ray_settings(w.st);
    cache::CacheState& cs = cache::cache_state(w.sc);
    auto tracer = [&](const float* o, const float* d, const uint32_t* k, const uint32_t* idx, size_t m, PathResult* r) {
        trace_given_rays(w.s, inner, o, d, k, idx, m, r, cs.inner, cs.inner_samples);
    };
    if (w.st.mode == IntegratorMode::Cache)
        cache::add_cached_indirect(w, tracer);
    else
        cache::place_guide_points(w, tracer);
}

// The stages, bounce after bounce, until every path of the batch has ended.
inline void run_paths(const Wavefront& w) {
    PathScratch& sc = w.sc;
    sc.sampler = w.st.sampler;  // what fill_uniforms draws the points' numbers from
    for (int depth = 0; !sc.active.empty(); ++depth) {
        const HitBatch hits = trace_bounce(w, depth);
        add_emission_and_environment(w, hits, depth);
        if (guide_recording::recording(sc)) guide_recording::note_arrivals(w);
        sc.timer.lap(Stage::Emission);
        group_by_material(w, hits, depth);
        sc.timer.lap(Stage::GroupMaterial);
        make_shading_points(w, hits, depth);
        sc.timer.times.shading_points += sc.sorted.size();
        sc.timer.lap(Stage::ShadingPoints);
        if (depth == 0 && w.st.mode != IntegratorMode::Path && w.st.max_depth > 1) run_cache_stage(w);
        if (w.st.mode == IntegratorMode::CacheGuided) cache::assign_guides(w, depth);
        queue_light_samples(w, depth);
        sample_bsdf(w, depth);
        if (guide_recording::recording(sc)) guide_recording::note_vertices(w);
        resolve_shadow_rays(w);
        std::swap(sc.active, sc.next_active);
        // the next bounce's rays, in its active order: update_paths wrote them (or none go on)
        std::swap(sc.ray_org, sc.next_ray_org);
        std::swap(sc.ray_dir, sc.next_ray_dir);
        sc.rays_gathered = true;
    }
}

inline bool scene_has_sun(const RenderScene& s) {
    for (const Light& l : s.lights)
        if (l.kind == LightKind::Sun) return true;
    return false;
}

// Sensor paths: path i starts at sensor sc.sensors[i] (its point, geometric normal and
// frame) along a cosine-weighted direction about its normal, drawn from the lens dimensions
// of w.cs[i].key (a sensor has no lens). A direction below the geometric surface (a bent
// shading normal) starts no path: it adds nothing, as the estimator of a sensor on that
// surface should. Throughput 1: the radiance found, times pi, is the illuminance estimate
// (E = integral of L cos over the hemisphere = pi x the mean of L under cosine sampling).
inline void start_sensor_paths(const Wavefront& w, size_t n) {
    start_paths(w, n);
    for (size_t i = 0; i < n; ++i) {
        const ShadingPoint& sp = w.sc.sensors[i];
        const CameraSample& c = w.cs[i];
        const float u1 = sample_uniform(w.st.sampler, c.key, c.index, 0, kDimLensU);
        const float u2 = sample_uniform(w.st.sampler, c.key, c.index, 0, kDimLensV);
        const float radius = std::sqrt(u1), phi = kTwoPi * u2;
        const Vec3f l{radius * std::cos(phi), radius * std::sin(phi), std::sqrt(std::max(1.0f - u1, 0.0f))};
        const Vec3f d = normalize(to_world(sp, l));
        if (dot(d, sp.ng) > 0) start_path(w, i, sp.p + w.eps * sp.ng, d);
    }
}

// The lux a sensor path's radiance stands for: pi x 683 lm/W x its luminance.
inline float sensor_path_lux(const PathResult& r) { return kPi * kLumensPerWatt * luminance(r.rgb); }

// Traces sc.sensor_samples.size() sensor paths from sc.sensors (start_sensor_paths) with at
// most st.max_depth vertices each, into sc.sensor_results.
inline void trace_sensor_paths(const RenderScene& s, const IntegratorSettings& st, PathScratch& sc) {
    const size_t n = sc.sensor_samples.size();
    sc.sensor_results.resize(n);
    IntegratorSettings inner = st;
    inner.indirect_illuminance = false;  // the sensors are not sensors again
    Wavefront w{s, inner, sc.sensor_samples.data(), sc.sensor_results.data(), sc, lights_emit(s), scene_has_sun(s),
                s.ray_offset};
    w.first_emission = false;
    start_sensor_paths(w, n);
    sc.timer.lap(Stage::CameraRays);  // a path's start counts as camera rays, a sensor's too
    run_paths(w);
}

// A sensor path's stream key: the key of the sample's stream, salted, so it draws numbers
// of its own (the same index: with Sobol, a pixel's sensor paths are one sequence too) and
// leaves the camera path's (and the direct light sampling's) unchanged.
inline uint32_t sensor_path_key(uint32_t key) { return hash_u32(key ^ 0x5f3759dfu); }

void trace_paths(const RenderScene& s, const IntegratorSettings& st, const CameraSample* cs, size_t n,
                 PathResult* out, PathScratch& sc) {
    enter_kernel();
    const Wavefront w{s, st, cs, out, sc, lights_emit(s), scene_has_sun(s), s.ray_offset};
    sc.sensors.clear();
    sc.timer.start();
    start_camera_paths(w, n);
    sc.timer.lap(Stage::CameraRays);
    if (guide_recording::recording(sc)) guide_recording::start_records(sc);
    run_paths(w);
    if (guide_recording::recording(sc)) guide_recording::finish_records(w);
    // the indirect illuminance AOV: each first hit a sensor, its path one vertex shorter
    if (!st.indirect_illuminance || st.max_depth < 2 || sc.sensors.empty()) return;
    sc.sensor_samples.resize(sc.sensors.size());
    for (size_t q = 0; q < sc.sensors.size(); ++q) {
        const CameraSample& c = cs[sc.sensors[q].path];
        sc.sensor_samples[q] = CameraSample{0, 0, sensor_path_key(c.key), c.index};
    }
    IntegratorSettings inner = st;
    inner.max_depth = st.max_depth - 1;
    inner.mode = IntegratorMode::Path;  // the sensors' paths are plain paths
    trace_sensor_paths(s, inner, sc);
    for (size_t q = 0; q < sc.sensors.size(); ++q)
        out[sc.sensors[q].path].illuminance += sensor_path_lux(sc.sensor_results[q]);
}

void trace_given_rays(const RenderScene& s, const IntegratorSettings& st, const float* org, const float* dir,
                      const uint32_t* keys, const uint32_t* indices, size_t n, PathResult* out, PathScratch& sc,
                      std::vector<CameraSample>& samples) {
    samples.resize(n);
    for (size_t i = 0; i < n; ++i) samples[i] = CameraSample{0.0f, 0.0f, keys[i], indices[i]};
    Wavefront w{s, st, samples.data(), out, sc, lights_emit(s), scene_has_sun(s), s.ray_offset};
    w.first_emission = false;
    start_given_paths(w, org, dir, n);
    run_paths(w);
}

// An image region's cache points (integrator.h, build_cache_region): the camera rays' first
// hits, then the cache's placement and building there (cache_stages_impl.h).
void build_cache_region(const RenderScene& s, const IntegratorSettings& st, const CameraSample* cs, size_t n,
                        std::vector<CachePoint>& points, std::vector<RegionHemisphere>& hemispheres, PathScratch& sc) {
    enter_kernel();
    std::vector<PathResult> out(n);
    const Wavefront w{s, st, cs, out.data(), sc, lights_emit(s), scene_has_sun(s), s.ray_offset};
    sc.sensors.clear();
    sc.timer.start();
    start_camera_paths(w, n);
    sc.timer.lap(Stage::CameraRays);
    const HitBatch hits = trace_bounce(w, 0);
    group_by_material(w, hits, 0);
    make_shading_points(w, hits, 0);
    sc.sensors.clear();
    sc.timer.lap(Stage::ShadingPoints);
    const IntegratorSettings inner = cache_ray_settings(st);
    cache::CacheState& cs_state = cache::cache_state(sc);
    auto tracer = [&](const float* o, const float* d, const uint32_t* k, const uint32_t* idx, size_t m, PathResult* r) {
        trace_given_rays(s, inner, o, d, k, idx, m, r, cs_state.inner, cs_state.inner_samples);
    };
    cache::build_region_points(w, tracer, points, hemispheres);
    sc.active.clear();
}

// The uniform sampler's jitter (integrator.h, jitter_pixel_positions): pixel-x and pixel-y
// numbers of N samples at a time, each lane the bits sample_uniform gives it.
void jitter_pixel_positions(SamplerKind kind, CameraSample* cs, size_t n) {
    enter_kernel();
    for_blocks(n, [&](size_t i, int lanes) {
        alignas(64) int32_t key[N] = {}, index[N] = {};
        alignas(64) float fx[N] = {}, fy[N] = {};
        uint32_t all = 0;
        for (int k = 0; k < lanes; ++k) {
            const CameraSample& c = cs[i + k];
            key[k] = static_cast<int32_t>(c.key);
            index[k] = static_cast<int32_t>(c.index);
            fx[k] = c.fx;
            fy[k] = c.fy;
            all |= c.index;
        }
        const I keys = load_n<N>(key), indices = load_n<N>(index);
        const int bits = bit_length(all);
        store_n<N>(fx, load_n<N>(fx) + sample_uniform_lanes(kind, keys, indices, bits, 0, kDimPixelX));
        store_n<N>(fy, load_n<N>(fy) + sample_uniform_lanes(kind, keys, indices, bits, 0, kDimPixelY));
        for (int k = 0; k < lanes; ++k) {
            cs[i + k].fx = fx[k];
            cs[i + k].fy = fy[k];
        }
    });
}

// The radiance cache at one point reprojected into another (integrator.h, cache_probe).
void cache_probe(const RenderScene& s, const IntegratorSettings& st, const float* pa, const float* na, const float* pb,
                 const float* nb, uint32_t seed, bool unknown_masks, CacheProbe& out) {
    enter_kernel();
    const CacheSettings& cfg = st.cache;
    check_cache_settings(cfg);
    const int R = cfg.resolution;
    const size_t T = static_cast<size_t>(R) * R;
    PathScratch sc;
    cache::CacheState& cs = cache::cache_state(sc);
    IntegratorSettings inner = st;
    inner.mode = IntegratorMode::Path;
    inner.indirect_illuminance = false;
    inner.max_depth = std::max(1, st.max_depth - 1);
    inner.rr_depth = std::max(1, st.rr_depth - 1);
    auto tracer = [&](const float* o, const float* d, const uint32_t* k, const uint32_t* idx, size_t m, PathResult* r) {
        trace_given_rays(s, inner, o, d, k, idx, m, r, cs.inner, cs.inner_samples);
    };
    auto query = [&](const float* p, const float* n, uint32_t key) {
        cache::Query q;
        q.p = load_vec3(p);
        q.n = q.ng = normalize(load_vec3(n));
        orthonormal_frame(q.n, q.t, q.b);
        q.key = key;
        return q;
    };
    const cache::Query q[2] = {query(pa, na, hash_u32(seed)), query(pb, nb, hash_u32(seed + 1))};
    cs.dirs.prepare(R);
    IntegratorSettings as_cache = st;  // A's glossy texel hits split as `cache` splits them
    as_cache.mode = IntegratorMode::Cache;
    cache::mark_split_materials(s.materials, as_cache, cs);
    // A, then B's own hemisphere in full (the reference)
    cs.used = 0;
    cs.pending = {0, 1};
    cache::build_cache_points(cfg, s.ray_offset, q, cs, tracer);
    const CachePoint& a = cs.points[0];
    out = CacheProbe{};
    out.resolution = R;
    out.a_radiance = a.radiance;
    out.a_dist = a.dist;
    out.a_kind = a.kind;
    out.a_layer.assign(T, -1);
    out.a_surfel.assign(T, -1);
    for (size_t k = 0; k < a.surfels.size(); ++k) {
        const Surfel& sf = a.surfels[k];
        for (int j = sf.j0; j < sf.j1; ++j)
            for (int i = sf.i0; i < sf.i1; ++i) {
                out.a_layer[static_cast<size_t>(j) * R + i] = sf.layer;
                out.a_surfel[static_cast<size_t>(j) * R + i] = static_cast<int32_t>(k);
            }
    }
    out.surfels = a.surfels.size();
    out.silhouettes = a.silhouettes.size();
    out.b_reference = cs.points[1].radiance;
    // B by reprojection, its holes traced
    out.b_reprojected.assign(3 * T, -1.0f);
    cache::reproject(a, cache::Receiver{q[1].p, q[1].t, q[1].b, q[1].n}, cs.dirs, out.b_reprojected.data(), cs.rep,
                     cs.rs, unknown_masks);
    out.filled.assign(T, 0);
    out.unknown.assign(T, 0);
    out.to_trace.assign(T, 0);
    out.b_radiance = out.b_reprojected;
    cs.rays.clear();
    const uint32_t key = cache::hole_key(q[1].key);
    for (size_t t = 0; t < T; ++t) {
        const int x = static_cast<int>(t % R), y = static_cast<int>(t / R);
        out.filled[t] = cs.rep.filled.test(x, y);
        out.unknown[t] = cs.rep.unknown.test(x, y);
        out.to_trace[t] = cs.rep.to_trace.test(x, y);
        if (!out.to_trace[t]) continue;
        std::fill(out.b_reprojected.begin() + 3 * t, out.b_reprojected.begin() + 3 * t + 3, -1.0f);
        std::fill(out.b_radiance.begin() + 3 * t, out.b_radiance.begin() + 3 * t + 3, 0.0f);
        const Vec3f d = cache::jittered_direction(q[1], R, static_cast<int32_t>(t), key);
        if (dot(d, q[1].ng) > 0)
            cs.rays.push(q[1].p + s.ray_offset * q[1].ng, d, key, static_cast<uint32_t>(t), static_cast<int32_t>(t));
    }
    cache::trace_queue(cs, tracer);
    for (size_t r = 0; r < cs.rays.size(); ++r)
        std::copy(cs.results[r].rgb, cs.results[r].rgb + 3, out.b_radiance.data() + 3 * cs.rays.where[r]);
}

// Sensor i (point and normal from the arrays) as shading point q: its frame about the normal.
inline ShadingPoint sensor_point(const float* points, const float* normals, size_t i, size_t q) {
    ShadingPoint sp;
    sp.p = load_vec3(points + 3 * i);
    sp.ng = normalize(load_vec3(normals + 3 * i));
    sp.n = sp.ng;
    orthonormal_frame(sp.n, sp.t, sp.b);
    sp.path = static_cast<int32_t>(q);
    sp.material = 0;
    sp.eta = 1;
    return sp;
}

// Direct illuminance on sensors (patina illuminance): the same light sampling and shadow
// packets as the renderer's, with the sensor's cosine instead of a BRDF.
void sensor_illuminance(const RenderScene& s, const float* points, const float* normals, size_t begin, size_t end,
                        int samples, uint32_t seed, float* lux, PathScratch& sc) {
    enter_kernel();
    sc.timer.start();  // its laps (in sample_lights) count as light sampling
    const size_t np = end - begin;
    std::fill(lux + begin, lux + end, 0.0f);
    if (np == 0 || !lights_emit(s)) return;
    sc.sorted.resize(np);
    for (size_t q = 0; q < np; ++q) sc.sorted[q] = sensor_point(points, normals, begin + q, q);
    const float eps = s.ray_offset;
    std::vector<double> sum(np, 0.0);
    sc.point_keys.resize(np);
    sc.point_index.resize(np);
    sc.sampler = SamplerKind::Independent;
    for (int k = 0; k < samples; ++k) {
        for (size_t q = 0; q < np; ++q) {
            const uint32_t key = stream_key(seed, static_cast<uint32_t>(begin + q));
            sc.point_keys[q] = static_cast<int32_t>(key);
            sc.point_index[q] = k;
        }
        sample_lights(s, sc, 0, np);
        clear_shadow_rays(sc);
        for (size_t q = 0; q < np; ++q) {
            if (!sc.ls_ok[q]) continue;
            const ShadingPoint& sp = sc.sorted[q];
            const LightSample ls = load_light_sample(sc, q);
            const float cos_s = dot(ls.dir, sp.n);
            if (!(cos_s > 0)) continue;
            const float none[3] = {0, 0, 0};
            queue_shadow_ray(sc, static_cast<int32_t>(q), sp.p, sp.n, eps, ls, none,
                             kLumensPerWatt * luminance(ls.rgb) * cos_s / ls.pdf);
        }
        const uint8_t* blocked = trace_shadow_rays(s, sc);
        for (size_t j = 0; j < sc.shadow_path.size(); ++j)
            if (!blocked[j]) sum[sc.shadow_path[j]] += sc.shadow_lux[j];
    }
    for (size_t q = 0; q < np; ++q) lux[begin + q] = static_cast<float>(sum[q] / samples);
}

// Indirect illuminance on sensors (patina illuminance --indirect): per sample, every sensor's
// path traced as one wavefront (trace_sensor_paths), its lux added to the sensor's sum.
void sensor_illuminance_indirect(const RenderScene& s, const IntegratorSettings& st, const float* points,
                                 const float* normals, size_t begin, size_t end, int samples, uint32_t seed,
                                 float* lux, PathScratch& sc) {
    enter_kernel();
    const size_t np = end - begin;
    if (np == 0 || !lights_emit(s) || st.max_depth < 1) return;
    std::vector<double> sum(np, 0.0);
    sc.sensors.resize(np);  // the sensor paths leave them as they are (no sensors of their own)
    for (size_t q = 0; q < np; ++q) sc.sensors[q] = sensor_point(points, normals, begin + q, q);
    sc.sensor_samples.resize(np);
    for (int k = 0; k < samples; ++k) {
        for (size_t q = 0; q < np; ++q) {
            const uint32_t key = stream_key(seed, static_cast<uint32_t>(begin + q));
            sc.sensor_samples[q] = CameraSample{0, 0, sensor_path_key(key), static_cast<uint32_t>(k)};
        }
        trace_sensor_paths(s, st, sc);
        for (size_t q = 0; q < np; ++q) sum[q] += sensor_path_lux(sc.sensor_results[q]);
    }
    for (size_t q = 0; q < np; ++q) lux[begin + q] += static_cast<float>(sum[q] / samples);
}

}  // namespace render_detail
PATINA_END_TARGET
