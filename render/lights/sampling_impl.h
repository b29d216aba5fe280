// Coherent light sampling (the thesis's coherent light sources; docs/render.md): one light
// sample per shading point. Each point picks a light in proportion to its estimated
// irradiance there (the selection, render/lights/selection_impl.h); the points are grouped by the
// light they picked, so every SIMD lane of a group samples the same light with the same code
// (coherent), N points at a time; their shadow rays are traced as packets
// (render/integrators/shadow_rays_impl.h). The densities here are also what the integrator's MIS weights need
// when a BRDF-sampled ray reaches a light.
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

#include "brdf/search.h"
#include "core/constants.h"
#include "core/simd/fastmath.h"
#include "core/simd/kernel_width.h"
#include "core/vec3.h"
#include "render/integrators/integrator.h"
#include "render/lights/delta_intensity_impl.h"
#include "render/lights/environment_impl.h"
#include "render/lights/selection_impl.h"
#include "render/samplers/rng.h"
#include "render/samplers/uniforms_impl.h"
#include "render/scene.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// --- MIS: light sampling against BRDF sampling ---

// Veach's power heuristic a^2 / (a^2 + b^2), written so near-delta pdfs cannot overflow.
inline float power_heuristic(float a, float b) {
    if (!(a > 0)) return 0.0f;
    if (!(b > 0)) return 1.0f;
    const float r = b / a;
    return 1.0f / (1.0f + r * r);
}

// Density (solid angle at the shading point `from`, selection included) with which light sampling
// reaches area light `li` (a quad or triangles: uniform by area) at distance `dist`, where
// the light's surface has cosine `facing` with the direction: the other strategy's density
// when a BRDF-sampled ray hits the light.
inline float area_light_pdf(const RenderScene& s, const Vec3f& from, int li, float facing, float dist) {
    const float cos_l = std::abs(facing);
    if (cos_l <= 0) return 0;
    return selection_probability(s, from, li) * dist * dist / (area_of(s.lights[li]).area * cos_l);
}

// One point's light sample (sample_lights leaves them in PathScratch's light_samples).
struct LightSample {
    Vec3f dir{0, 0, 0};        // unit, from the shading point
    float dist = 0;            // to the light point (inf: environment)
    float rgb[3] = {0, 0, 0};  // radiance (W/(m^2 sr)), or intensity / dist^2 for a point light
    float pdf = 0;             // solid-angle pdf including selection; for a point light the selection probability
    bool delta = false;        // a point light: no MIS
};

inline LightSample load_light_sample(const PathScratch& sc, size_t q) {
    LightSample ls;
    ls.dir = load_vec3(sc.light_samples.dir.data() + 3 * q);
    std::copy(sc.light_samples.rgb.data() + 3 * q, sc.light_samples.rgb.data() + 3 * q + 3, ls.rgb);
    ls.dist = sc.light_samples.dist[q];
    ls.pdf = sc.light_samples.pdf[q];
    ls.delta = sc.light_samples.delta[q] != 0;
    return ls;
}

// --- sampling: N points of one light at a time ---

// N points' samples of one light: directions (unit, from the points), RGB (radiance, or
// intensity / dist^2 for a delta light), distances, pdfs (selection included).
struct LightSampleBlock {
    V3 dir;
    F r, g, b;
    F dist;
    F pdf;
};

// The sun: a direction uniform in its disc's cone (pdf 1 / (2 pi (1 - cos))), its radiance.
PATINA_INLINE F sample_sun(const SunLight& l, F u1, F u2, V3& w, F& r, F& g, F& b) {
    // 1 - cos(theta) = u1 (1 - cos_sun), uniform over the cone; sin from it without cancellation
    const F one_minus = u1 * F(l.one_minus_cos);
    const F cos_t = F(1.0f) - one_minus;
    const F sin_t = sqrt_exact(max(one_minus * (F(2.0f) - one_minus), F(0.0f)));
    F sp, cp;
    fast_sincos(F(2.0f * kPi) * u2, sp, cp);
    const F a = sin_t * cp, c = sin_t * sp;
    w = V3{madd(a, F(l.frame_t[0]), madd(c, F(l.frame_b[0]), cos_t * F(l.direction[0]))),
           madd(a, F(l.frame_t[1]), madd(c, F(l.frame_b[1]), cos_t * F(l.direction[1]))),
           madd(a, F(l.frame_t[2]), madd(c, F(l.frame_b[2]), cos_t * F(l.direction[2])))};
    r = F(l.radiance[0]), g = F(l.radiance[1]), b = F(l.radiance[2]);
    return F(1.0f / (2.0f * kPi * l.one_minus_cos));
}

// A point uniform by area over a triangle light's triangles (the triangle by its area cdf,
// u1 reused within the cell), with that triangle's geometric normal.
PATINA_INLINE V3 sample_triangles(const RenderScene& s, const TriangleLight& l, F u1, F u2, V3& n) {
    const int count = static_cast<int>(l.triangles.size());
    const I k = coherent_search<N>(l.area_cdf.data(), count + 1, u1, F(0.0f) == F(0.0f));
    const F c0 = gather(l.area_cdf.data(), k), c1 = gather(l.area_cdf.data(), k + I(1));
    const F r1 = select(c1 > c0, clamp((u1 - c0) / (c1 - c0), F(0.0f), F(1.0f)), F(0.5f));
    const I tri = gather(l.triangles.data(), k);
    const float* v = s.tree->triangles.data();
    const I base = tri * I(9), nb = tri * I(3);
    V3 p[3];
    for (int j = 0; j < 3; ++j)
        p[j] = V3{gather(v, base + I(3 * j)), gather(v, base + I(3 * j + 1)),
                  gather(v, base + I(3 * j + 2))};
    n = V3{gather(s.tree->normals.data(), nb), gather(s.tree->normals.data(), nb + I(1)),
           gather(s.tree->normals.data(), nb + I(2))};
    const F su = sqrt_exact(r1), b0 = F(1.0f) - su, b1 = su * (F(1.0f) - u2), b2 = su * u2;
    return V3{madd(b0, p[0].x, madd(b1, p[1].x, b2 * p[2].x)), madd(b0, p[0].y, madd(b1, p[1].y, b2 * p[2].y)),
              madd(b0, p[0].z, madd(b1, p[1].z, b2 * p[2].z))};
}

// The distance from `at` to `target`, the unit direction there into w, the squared distance
// into dist2.
PATINA_INLINE F towards(const V3& at, const V3& target, V3& w, F& dist2) {
    const F dx = target.x - at.x, dy = target.y - at.y, dz = target.z - at.z;
    dist2 = dx * dx + dy * dy + dz * dz;
    const F d = sqrt_exact(dist2);
    const F inv = F(1.0f) / d;
    w = V3{dx * inv, dy * inv, dz * inv};
    return d;
}

// A point `target` of normal n on an area light, seen from `at`.
PATINA_INLINE LightSampleBlock area_sample(const AreaLight& l, const V3& at, const V3& target, const V3& n, F sel) {
    LightSampleBlock out;
    F dist2;
    out.dist = towards(at, target, out.dir, dist2);
    // emitting side: -dir . n > 0, or either side when two-sided
    const V3& w = out.dir;
    const F facing = -(w.x * n.x + w.y * n.y + w.z * n.z);
    const F cos_l = l.two_sided ? abs(facing) : facing;
    out.r = F(l.radiance[0]), out.g = F(l.radiance[1]), out.b = F(l.radiance[2]);
    out.pdf = select((cos_l > F(0.0f)) & (dist2 > F(0.0f)), sel * dist2 / (F(l.area) * cos_l), F(0.0f));
    return out;
}

// A delta light of RGB intensity `rgb` (times its relative intensity towards the point) seen
// from `at`: intensity / distance^2.
template <class Delta>
PATINA_INLINE LightSampleBlock delta_sample(const Delta& l, const float rgb[3], const V3& at, F sel) {
    LightSampleBlock out;
    F dist2;
    out.dist = towards(at, V3{F(l.position[0]), F(l.position[1]), F(l.position[2])}, out.dir, dist2);
    const V3& w = out.dir;
    const F scale = relative_intensity<N>(l, V3{-w.x, -w.y, -w.z}) / dist2;
    out.r = F(rgb[0]) * scale, out.g = F(rgb[1]) * scale, out.b = F(rgb[2]) * scale;
    out.pdf = select(dist2 > F(0.0f), sel, F(0.0f));
    return out;
}

// Each kind's samples for points `at` (not read at infinity) from (u1, u2), selected with
// probability sel.
PATINA_INLINE LightSampleBlock sample(const PointLight& l, const RenderScene&, const V3& at, F, F, F sel) {
    return delta_sample(l, l.intensity, at, sel);
}
PATINA_INLINE LightSampleBlock sample(const SpotLight& l, const RenderScene&, const V3& at, F, F, F sel) {
    return delta_sample(l, l.intensity, at, sel);
}
PATINA_INLINE LightSampleBlock sample(const GoniometricLight& l, const RenderScene&, const V3& at, F, F, F sel) {
    return delta_sample(l, l.rgb_per_candela, at, sel);
}
PATINA_INLINE LightSampleBlock sample(const QuadLight& l, const RenderScene&, const V3& at, F u1, F u2, F sel) {
    // a uniform point on the parallelogram
    const F ua = madd(F(2.0f), u1, F(-1.0f)), ub = madd(F(2.0f), u2, F(-1.0f));
    const V3 target{madd(ua, F(l.u[0]), madd(ub, F(l.v[0]), F(l.center[0]))),
                    madd(ua, F(l.u[1]), madd(ub, F(l.v[1]), F(l.center[1]))),
                    madd(ua, F(l.u[2]), madd(ub, F(l.v[2]), F(l.center[2])))};
    return area_sample(l, at, target, V3{F(l.normal[0]), F(l.normal[1]), F(l.normal[2])}, sel);
}
PATINA_INLINE LightSampleBlock sample(const TriangleLight& l, const RenderScene& s, const V3& at, F u1, F u2,
                                      F sel) {
    V3 n;
    const V3 target = sample_triangles(s, l, u1, u2, n);
    return area_sample(l, at, target, n, sel);
}
PATINA_INLINE LightSampleBlock sample(const SunLight& l, const RenderScene&, const V3&, F u1, F u2, F sel) {
    LightSampleBlock out;
    out.pdf = sample_sun(l, u1, u2, out.dir, out.r, out.g, out.b) * sel;
    out.dist = F(kInfinity);
    return out;
}

// How many blocks ahead the environment's sampling prefetches its cdf lines: far enough
// for an L3 miss to arrive, near enough that the lines are still in L1/L2 when searched.
constexpr size_t kEnvPrefetchBlocks = 4;

// Light samples for the points that chose light `li` (every lane the same light: coherent),
// N points at a time: inputs gathered from the points, results scattered back to sc.light_samples.
inline void sample_light_group(const RenderScene& s, PathScratch& sc, int li, const int32_t* points, size_t n,
                               const float* u1, const float* u2) {
    float* pos = grow(sc.group_pos, 3 * n);
    float* g1 = grow(sc.group_u1, n);
    float* g2 = grow(sc.group_u2, n);
    float* dir = grow(sc.group_dir, 3 * n);
    float* rgb = grow(sc.group_rgb, 3 * n);
    float* dist = grow(sc.group_dist, n);
    float* pdf = grow(sc.group_pdf, n);
    float* gsel = grow(sc.group_sel, n);
    const bool env = li == static_cast<int>(s.lights.size());
    const Light* light = env ? nullptr : &s.lights[li];
    // the points' positions do not matter for the environment and the sun
    const bool at_infinity =
        env || visit_kind(*light, [](const auto& kind) { return std::decay_t<decltype(kind)>::at_infinity; });
    for (size_t j = 0; j < n; ++j) {
        const int32_t q = points[j];
        if (!at_infinity) store_vec3(sc.sorted[q].p, pos + 3 * j);
        g1[j] = u1[q];
        g2[j] = u2[q];
        gsel[j] = sc.point_sel[q];
    }
    const auto store = [&](size_t i, int lanes, const LightSampleBlock& out) {
        store_rows(dir, i, lanes, out.dir);
        store_rows(rgb, i, lanes, out.r, out.g, out.b);
        store_lanes(dist, i, lanes, out.dist);
        store_lanes(pdf, i, lanes, out.pdf);
    };
    if (env) {
        for_blocks(n, [&](size_t i, int lanes) {
            const F s1 = load_lanes(g1, i, lanes), s2 = load_lanes(g2, i, lanes);
            const F sel = load_lanes(gsel, i, lanes);
            // the cdf lines of the block kEnvPrefetchBlocks ahead on their way while this one waits
            const size_t ahead = i + kEnvPrefetchBlocks * N;
            if (ahead < n) {
                const int la = static_cast<int>(std::min<size_t>(N, n - ahead));
                env_w::prefetch_sample(s.env, load_lanes(g1, ahead, la), load_lanes(g2, ahead, la));
            }
            LightSampleBlock out;
            out.pdf = sel * env_w::sample(s.env, s1, s2, out.dir, out.r, out.g, out.b);
            out.dist = F(kInfinity);
            store(i, lanes, out);
        });
    } else {
        visit_kind(*light, [&](const auto& kind) {
            for_blocks(n, [&](size_t i, int lanes) {
                const F s1 = load_lanes(g1, i, lanes), s2 = load_lanes(g2, i, lanes);
                const F sel = load_lanes(gsel, i, lanes);
                V3 at{F(0.0f), F(0.0f), F(0.0f)};
                if constexpr (!std::decay_t<decltype(kind)>::at_infinity) at = load_rows(pos, i, lanes);
                store(i, lanes, sample(kind, s, at, s1, s2, sel));
            });
        });
    }
    const bool delta = light != nullptr && is_delta_light(*light);
    for (size_t j = 0; j < n; ++j) {
        const int32_t q = points[j];
        std::copy(dir + 3 * j, dir + 3 * j + 3, sc.light_samples.dir.data() + 3 * q);
        std::copy(rgb + 3 * j, rgb + 3 * j + 3, sc.light_samples.rgb.data() + 3 * q);
        sc.light_samples.dist[q] = dist[j];
        sc.light_samples.pdf[q] = pdf[j];
        sc.light_samples.delta[q] = delta;
        sc.light_samples.usable[q] = pdf[j] > 0 && std::isfinite(pdf[j]);
    }
}

// One light sample per shading point into sc.light_samples: each point picks a light in proportion to
// its estimated irradiance there, the points are grouped by the light they picked, and each
// group is sampled N points at a time.
inline void sample_lights(const RenderScene& s, PathScratch& sc, int depth, size_t np) {
    sc.light_samples.dir.resize(3 * np);
    sc.light_samples.rgb.resize(3 * np);
    sc.light_samples.dist.resize(np);
    sc.light_samples.pdf.resize(np);
    sc.light_samples.delta.resize(np);
    sc.light_samples.usable.resize(np);
    float* pick = grow(sc.u_pick, np);
    float* u1 = grow(sc.uniform_u, np);
    float* u2 = grow(sc.uniform_v, np);
    const int count = light_count(s);
    // one light (an environment alone, say) is picked whatever the number: none drawn
    if (count > 1) fill_uniforms(sc, np, depth, kDimLightPick, pick);
    else std::fill(pick, pick + np, 0.0f);
    fill_uniforms(sc, np, depth, kDimLightU, u1);
    fill_uniforms(sc, np, depth, kDimLightV, u2);
    std::vector<int32_t>& chosen = sc.light_of_point;
    chosen.resize(np);
    sc.point_sel.resize(np);
    sc.light_start.assign(count + 1, 0);
    float* pos = nullptr;  // the points' positions, when a weight depends on them
    if (selection_is_local(s)) {
        pos = grow(sc.selection_pos, 3 * np);
        for (size_t q = 0; q < np; ++q) store_vec3(sc.sorted[q].p, pos + 3 * q);
    }
    float* w = grow(sc.selection_weights, (count + 1) * np);  // count rows of weights, then the sums
    float* sum = w + count * np;
    points_selection_weights(s, pos, np, w, sum);
    for (size_t q = 0; q < np; ++q) {
        chosen[q] = pick_light(w + q, np, count, sum[q], pick[q], sc.point_sel[q]);
        ++sc.light_start[chosen[q] + 1];
    }
    // grouped by light (a counting sort, each group in the points' order), then sampled group by group
    for (int k = 0; k < count; ++k) sc.light_start[k + 1] += sc.light_start[k];
    sc.light_points.resize(np);
    sc.light_fill.assign(sc.light_start.begin(), sc.light_start.end() - 1);
    for (size_t q = 0; q < np; ++q) sc.light_points[sc.light_fill[chosen[q]]++] = static_cast<int32_t>(q);
    sc.timer.lap(Stage::LightSelect);
    for (int k = 0; k < count; ++k) {
        const size_t a = sc.light_start[k], n = sc.light_start[k + 1] - a;
        if (n > 0) sample_light_group(s, sc, k, sc.light_points.data() + a, n, u1, u2);
    }
    sc.timer.lap(Stage::LightSample);
}

}  // namespace render_detail
PATINA_END_TARGET
