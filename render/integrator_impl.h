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
#include "render/camera.h"
#include "render/env_impl.h"
#include "render/integrator.h"
#include "render/light_sampling_impl.h"
#include "render/material_impl.h"
#include "render/rng.h"
#include "render/sample_numbers.h"
#include "render/scene.h"
#include "render/shadow_rays_impl.h"
#include "render/uniforms_impl.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// A world direction in a shading point's frame, and back.
inline Vec3f to_local(const ShadingPoint& sp, const Vec3f& d) { return {dot(d, sp.t), dot(d, sp.b), dot(d, sp.n)}; }
inline Vec3f to_world(const ShadingPoint& sp, const Vec3f& l) { return l.x * sp.t + l.y * sp.b + l.z * sp.n; }

// Fills the shading point of a hit: interpolated normal and tangent, frame, facing. False
// when the path ends here (the back of a one-sided surface).
inline bool make_shading_point(const RenderScene& s, int32_t prim, float u, float v, const Vec3f& org,
                               const Vec3f& dir, float t, ShadingPoint& sp) {
    const Material& m = s.materials[s.tri_material[prim]];
    const int32_t* tri = s.indices + 3 * static_cast<size_t>(prim);
    const float w0 = 1.0f - u - v;
    // a per-vertex attribute interpolated at the hit
    auto interpolate = [&](const float* a) {
        return w0 * load_vec3(a + 3 * tri[0]) + u * load_vec3(a + 3 * tri[1]) + v * load_vec3(a + 3 * tri[2]);
    };
    sp.p = org + t * dir;
    sp.ng = load_vec3(s.tree->normals.data() + 3 * static_cast<size_t>(prim));
    sp.n = normalize(interpolate(s.normals));
    const Vec3f wo = -dir;
    const bool transmissive = m.kind == MaterialKind::Dielectric;
    // the geometric normal (from the winding) points out of a closed dielectric
    sp.eta = transmissive ? (dot(sp.ng, wo) < 0 ? 1.0f / m.eta[0] : m.eta[0]) : 1.0f;
    if (dot(sp.ng, wo) < 0) {
        if (!m.two_sided && !transmissive) return false;
        sp.ng = -sp.ng;
        sp.n = -sp.n;
    } else if (dot(sp.n, sp.ng) < 0) {
        sp.n = -sp.n;  // a mesh whose normals point inwards
    }
    // a shading normal facing away from the viewer (silhouettes of coarse meshes): use the true one
    if (!(dot(sp.n, wo) > 0)) sp.n = sp.ng;
    if (s.tangents != nullptr) {
        Vec3f tangent = interpolate(s.tangents);
        tangent = tangent - dot(tangent, sp.n) * sp.n;
        if (dot(tangent, tangent) > 1e-12f) {
            sp.t = normalize(tangent);
            sp.b = cross(sp.n, sp.t);
            return true;
        }
    }
    orthonormal_frame(sp.n, sp.t, sp.b);
    return true;
}

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
    sc.cached.clear();  // none served by the radiance cache (start_camera_paths says otherwise)
    sc.guide_of.clear();
    for (size_t i = 0; i < n; ++i) {
        PathResult& r = w.out[i];
        std::fill(r.rgb, r.rgb + 3, 0.0f);
        std::fill(r.albedo, r.albedo + 3, 0.0f);
        std::fill(r.normal, r.normal + 3, 0.0f);
        r.depth = kInfinity;
        r.illuminance = 0;
    }
}

// The batch's camera rays, with throughput 1 and empty results; every path active.
inline void start_camera_paths(const Wavefront& w, size_t n) {
    start_paths(w, n);
    const bool lens = w.s.camera.aperture_radius > 0;  // a pinhole draws no lens numbers
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
// BRDF sample) the density of light sampling; and the sun's disc, where they go through it.
inline void add_environment(const Wavefront& w) {
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
    if (s.env.present) for_blocks(n, [&](size_t i, int lanes) {
        const V3 dirs = load_rows(d, i, lanes);
        F r, g, b;
        env_w::radiance(s.env, dirs, r, g, b);
        store_rows(le, i, lanes, r, g, b);
        store_lanes(lp, i, lanes, env_w::pdf(s.env, dirs));
    });
    const int env_light = static_cast<int>(s.lights.size());
    for (size_t j = 0; j < n; ++j) {
        const int32_t i = sc.misses[j];
        const Vec3f from = load_vec3(sc.prev_pos.data() + 3 * i);
        const bool mis = prev_pdf[i] > 0 && w.can_sample_lights;  // after a BRDF sample (not a camera ray)
        if (s.env.present) {
            const float wt =
                mis ? power_heuristic(prev_pdf[i], selection_probability(s, from, env_light) * lp[j]) : 1.0f;
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
    add_environment(w);
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

// 3. Grouping by material before the points exist: the hits that may become shading points
//    counted per material (sc.material_start: each group's first slot in sc.sorted), so
//    make_shading_points writes each point straight into its group, in hit order (what a
//    stable counting sort of the points would give, without building and copying them twice).
inline void group_by_material(const Wavefront& w, const HitBatch& hits, int depth) {
    PathScratch& sc = w.sc;
    const size_t nm = w.s.materials.size();
    sc.material_start.assign(nm + 1, 0);
    for (size_t j = 0; j < sc.active.size(); ++j)
        if (may_shade(w, hits, j, depth)) ++sc.material_start[w.s.tri_material[hits.prim[j]] + 1];
    for (size_t k = 0; k < nm; ++k) sc.material_start[k + 1] += sc.material_start[k];
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
    std::vector<int32_t>& fill = sc.next_active;  // reused as the write cursors
    fill.assign(sc.material_start.begin(), sc.material_start.end() - 1);
    for (size_t j = 0; j < sc.active.size(); ++j) {
        if (!may_shade(w, hits, j, depth)) continue;
        const int32_t i = sc.active[j];
        const int32_t prim = hits.prim[j];
        const int32_t material = s.tri_material[prim];
        const size_t q = fill[material];
        ShadingPoint& sp = sc.sorted[q];
        const Vec3f dir = load_vec3(sc.dir.data() + 3 * i);
        if (!make_shading_point(s, prim, hits.u[j], hits.v[j], load_vec3(sc.org.data() + 3 * i), dir, hits.t[j], sp)) {
            if (depth == 0) w.out[i].depth = hits.t[j];
            continue;  // the slot is taken by the group's next point
        }
        ++fill[material];
        sp.path = i;
        sp.material = material;
        if (depth == 0) {
            const Material& mat = s.materials[material];
            std::copy(mat.albedo, mat.albedo + 3, w.out[i].albedo);
            store_vec3(sp.n, w.out[i].normal);
            w.out[i].depth = hits.t[j];
            if (w.st.indirect_illuminance) sc.sensors.push_back(sp);
        }
        store_vec3(to_local(sp, -dir), vl + 3 * q);
        eta[q] = sp.eta;
        sc.point_keys[q] = static_cast<int32_t>(w.cs[i].key);
        sc.point_index[q] = static_cast<int32_t>(w.cs[i].index);
    }
    // paths that ended at a hit (the back of a one-sided surface) left their group short:
    // close the gaps, groups in order
    size_t np = 0;
    for (size_t k = 0; k < nm; ++k) {
        const size_t a = sc.material_start[k], count = fill[k] - a;
        sc.material_start[k] = np;
        if (a != np) {
            std::copy(sc.sorted.begin() + a, sc.sorted.begin() + a + count, sc.sorted.begin() + np);
            std::copy(vl + 3 * a, vl + 3 * (a + count), vl + 3 * np);
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
    if (depth == 0 && w.st.mode == IntegratorMode::CacheGuided) cache::mix_light_pdfs(sc, w.st.cache, ll, pdf, np);
    sc.timer.lap(Stage::ShadeLight);
    for (size_t q = 0; q < np; ++q) {
        if (!sc.ls_ok[q]) continue;
        const ShadingPoint& sp = sc.sorted[q];
        const LightSample ls = load_light_sample(sc, q);
        const float lz = ll[3 * q + 2], cos_l = std::abs(lz);
        if (!(cos_l > 0)) continue;
        const float wt = ls.delta ? 1.0f : power_heuristic(ls.pdf, pdf[q]);
        const float* T = sc.throughput.data() + 3 * sp.path;
        float c[3];
        for (int k = 0; k < 3; ++k) c[k] = T[k] * fv[3 * q + k] * cos_l * ls.rgb[k] * wt / ls.pdf;
        const float lux = depth == 0 && lz > 0 ? kLumensPerWatt * luminance(ls.rgb) * cos_l / ls.pdf : 0.0f;
        const float side = lz > 0 ? w.eps : -w.eps;
        if (c[0] <= 0 && c[1] <= 0 && c[2] <= 0 && lux <= 0) continue;
        queue_shadow_ray(sc, sp.path, sp.p, sp.ng, side, ls, c, lux);
    }
    sc.timer.lap(Stage::ShadowQueue);
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
    fill_uniforms(sc, np, depth, kDimBsdfPick, upick);
    fill_uniforms(sc, np, depth, kDimBsdfU, u1);
    fill_uniforms(sc, np, depth, kDimBsdfV, u2);
    sc.timer.lap(Stage::BsdfUniforms);
    const bool guided = depth == 0 && w.st.mode == IntegratorMode::CacheGuided;
    if (guided) cache::guided_picks(w);
    for_material_groups(w, [&](const Material& m, size_t a, size_t count) {
        material_sample(m, vl + 3 * a, eta + a, upick + a, u1 + a, u2 + a, ll + 3 * a, pdf + a, count);
        material_eval(m, ll + 3 * a, vl + 3 * a, eta + a, fv + 3 * a, count);
    });
    if (guided) cache::guided_directions(w);
    sc.timer.lap(Stage::ShadeSample);
    sc.next_active.clear();
    for (size_t q = 0; q < np; ++q) {
        const ShadingPoint& sp = sc.sorted[q];
        const int32_t i = sp.path;
        const Vec3f l = load_vec3(ll + 3 * q);
        if (!(pdf[q] > 0) || l.z == 0 || depth + 1 > w.st.max_depth) continue;
        const Vec3f wl = normalize(to_world(sp, l));
        if (!(dot(wl, sp.ng) * l.z > 0)) continue;  // the side the local direction says
        float* T = sc.throughput.data() + 3 * i;
        for (int k = 0; k < 3; ++k) T[k] *= fv[3 * q + k] * std::abs(l.z) / pdf[q];
        if (!(T[0] > 0 || T[1] > 0 || T[2] > 0)) continue;
        if (depth + 1 >= w.st.rr_depth) {
            const float survive = std::min(0.95f, std::max(T[0], std::max(T[1], T[2])));
            if (sample_uniform(w.st.sampler, w.cs[i].key, w.cs[i].index, depth, kDimRoulette) >= survive) continue;
            for (int k = 0; k < 3; ++k) T[k] /= survive;
        }
        const float side = l.z > 0 ? w.eps : -w.eps;
        store_vec3(sp.p + side * sp.ng, sc.org.data() + 3 * i);
        store_vec3(wl, sc.dir.data() + 3 * i);
        sc.prev_pdf[i] = pdf[q];
        store_vec3(sp.p, sc.prev_pos.data() + 3 * i);
        sc.next_active.push_back(i);
    }
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
        cache::build_guides(w, tracer);
}

// The stages, bounce after bounce, until every path of the batch has ended.
inline void run_paths(const Wavefront& w) {
    PathScratch& sc = w.sc;
    sc.sampler = w.st.sampler;  // what fill_uniforms draws the points' numbers from
    for (int depth = 0; !sc.active.empty(); ++depth) {
        const HitBatch hits = trace_bounce(w, depth);
        add_emission_and_environment(w, hits, depth);
        sc.timer.lap(Stage::Emission);
        group_by_material(w, hits, depth);
        sc.timer.lap(Stage::GroupMaterial);
        make_shading_points(w, hits, depth);
        sc.timer.times.shading_points += sc.sorted.size();
        sc.timer.lap(Stage::ShadingPoints);
        if (depth == 0 && w.st.mode != IntegratorMode::Path && w.st.max_depth > 1) run_cache_stage(w);
        queue_light_samples(w, depth);
        sample_bsdf(w, depth);
        resolve_shadow_rays(w);
        std::swap(sc.active, sc.next_active);
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
    run_paths(w);
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
                        std::vector<CachePoint>& points, PathScratch& sc) {
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
    cache::build_region_points(w, tracer, points);
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
