// cache-guided's stages in the wavefront integrator (render/integrators/cache_guided_impl.h calls them), compiled
// once per width: at the first hit the batch's cache points where they guide (the regions'
// shared points, and points of its own for first hits none of them serves:
// place_cache_points), then at every bounce each shading point's guide (a cache point's,
// guided_bounces_impl.h, or the trained guide's, render/guiding/guide_field.h), the light
// samples' MIS densities against the guide/BRDF mixture, and the mixture's one-sample
// choice when the next direction is drawn.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/simd/kernel_width.h"
#include "core/vec3.h"
#include "render/cache/cache_stages_impl.h"
#include "render/cache/guided_bounces_impl.h"
#include "render/cache/radiance_cache_impl.h"
#include "render/integrators/integrator.h"
#include "render/materials/material_impl.h"

PATINA_BEGIN_TARGET
namespace cache {

// Whether the first bounce draws from the cache points: only without a trained guide
// (cache.train_passes 0), whose full incident radiance guides the first bounce better than
// the cache points' direct light at their hits (docs/radiance-cache.md, "The trained
// guide"); never in a training pass, whose vertices are recorded for the guide alone.
inline bool cache_points_guide(const PathScratch& sc, const CacheSettings& cfg) {
    return sc.guide_sink == nullptr && cfg.train_passes == 0;
}

// cache-guided, at the first hit: the cache points this batch's guides come from -- the
// shared points, and points of its own for the first hits (queries, as `cache` makes them)
// that none of those serves.
template <class W, class Tracer>
inline void place_guide_points(const W& w, Tracer& trace) {
    if (!cache_points_guide(w.scratch, w.settings.cache)) return;
    CacheState& cache = start_cache_stage(w);
    const size_t rays_before = cache.inner.rays_traced;
    const std::vector<Query>& queries = cache.table.queries;
    place_cache_points(w.settings.cache, w.ray_offset, queries.data(), queries.size(), cache, trace);
    w.scratch.cache_points += cache.build.used;
    w.scratch.cache_queries += cache.table.queries.size();
    w.scratch.rays_traced += cache.inner.rays_traced - rays_before;
    if (cache.build.pool.empty())  // no queries: the shared points alone
        for (const CachePoint* a : w.scratch.cache_shared) cache.build.pool.push_back(a);
    cache.guides.prepare(cache.build.pool, w.settings.cache.resolution);
    cache.lap(Stage::CachePlace);
}

// The bounces the cache points guide: the first hit's. Guiding every bounce from the same
// points (the later vertices' nearest cache point, the tile's regions and their
// neighbours') was measured on the bundled scenes at 64 pixels wide, 16 spp: the room's
// variance fell 23 %, the studio's and the IES interior's rose 39 and 51 %, as the later
// vertices' light is less like any cache point's; the first hit alone: -17 %, +15 %, +17 %
// at less cost. With a trained guide (render/guiding/guide_field.h) the first
// cache.train_bounces bounces draw from it instead.
constexpr int kGuidedBounces = 1;

// The materials the trained guide draws for: lobes broad enough for its cells (a narrow lobe
// is its BRDF's to sample; the mixture would only halve its samples), no clear coat (a
// near-mirror over the base) and no glass. Measured (docs/radiance-cache.md): guiding the
// IES interior's plastic floor too (proxy roughness between 0.1 and 0.3) raised its relMSE
// at 16 spp by a fifth.
constexpr float kFieldMinAlpha = 0.3f;
inline bool field_guidable(const Material& m) {
    if (m.coat) return false;
    const std::optional<float> alpha = reflection_alpha(m);
    return alpha && *alpha >= kFieldMinAlpha;
}

// cache-guided, at every bounce before light sampling: each shading point's guide -- at the
// first bounce its cache point (cache.guides.cache_point_of) where the cache points guide, for the
// materials whose lobes the texels resolve; else, at the first cache.train_bounces bounces,
// its trained guide's distribution (cache.guides.field_of), for the materials field_guidable
// takes.
template <class W>
inline void assign_guides(const W& w, int depth) {
    PathScratch& sc = w.scratch;
    CacheState& cache = cache_state(sc);
    GuidePool& g = cache.guides;
    const int R = w.settings.cache.resolution;
    const size_t np = sc.sorted.size();
    g.cache_point_of.assign(np, -1);
    g.field_of.assign(np, -1);
    g.any = false;
    g.field = sc.guide_field;
    if (depth < kGuidedBounces && !g.points.empty() && g.resolution == R) {
        cache.texel_directions.prepare(R);
        for (size_t k = 0; k < w.scene.materials.size(); ++k) {
            if (!texel_resolvable(w.scene.materials[k], R)) continue;
            const size_t first = sc.material_start[k], last = sc.material_start[k + 1];
            for (size_t q = first; q < last; ++q) {
                const ShadingPoint& sp = sc.sorted[q];
                const int32_t a = g.find(sp.p, sp.n);
                if (a >= 0 && g.guide(a, cache.texel_directions)) g.cache_point_of[q] = a, g.any = true;
            }
        }
    }
    if (g.field != nullptr && !g.field->empty() && depth < w.settings.cache.train_bounces)
        for (size_t k = 0; k < w.scene.materials.size(); ++k) {
            if (!field_guidable(w.scene.materials[k])) continue;
            const size_t first = sc.material_start[k], last = sc.material_start[k + 1];
            for (size_t q = first; q < last; ++q) {
                if (g.cache_point_of[q] >= 0) continue;
                const ShadingPoint& sp = sc.sorted[q];
                const float at[3] = {sp.p.x, sp.p.y, sp.p.z}, n[3] = {sp.n.x, sp.n.y, sp.n.z};
                g.field_of[q] = g.field->distribution_at(at, n);
                g.any = g.any || g.field_of[q] >= 0;
            }
        }
    sc.timer.lap(Stage::CacheIntegrate);
}

// The probability of the guide's strategy in the mixture: cache.guide for the cache points',
// cache.train_guide for the trained guide's (one a bounce: the two never guide one bounce).
inline float guide_probability(const GuidePool& g, const CacheSettings& cfg) {
    return g.field != nullptr ? cfg.train_guide : cfg.guide;
}

inline bool guided_here(const PathScratch& sc) {
    if (!sc.cache) return false;
    const GuidePool& g = static_cast<const CacheState*>(sc.cache.get())->guides;
    return g.any && g.cache_point_of.size() == sc.sorted.size();
}

// The guide's density at point q's local direction l (0 without a guide).
inline float guide_density(const PathScratch& sc, const GuidePool& g, size_t q, const float* l) {
    const int32_t a = g.cache_point_of[q];
    if (a < 0 && g.field_of[q] < 0) return 0.0f;
    const ShadingPoint& sp = sc.sorted[q];
    const Vec3f d = l[0] * sp.t + l[1] * sp.b + l[2] * sp.n;
    if (a < 0) {
        const Vec3f u = normalize(d);
        const float dir[3] = {u.x, u.y, u.z};
        return g.field->pdf(g.field_of[q], dir);
    }
    const size_t T = static_cast<size_t>(g.resolution) * g.resolution;
    return pool_guide_pdf(*g.points[a], g.cdf.data() + static_cast<size_t>(a) * T, g.resolution, d);
}

// cache-guided, light sampling: the BRDF-sampling density each light sample's MIS weight
// compares with is the mixture's at the guided points.
inline void mix_light_pdfs(const PathScratch& sc, const CacheSettings& cfg, const float* l, float* pdf, size_t n) {
    if (!guided_here(sc)) return;
    const GuidePool& g = static_cast<const CacheState*>(sc.cache.get())->guides;
    const float a = guide_probability(g, cfg);
    for (size_t q = 0; q < n; ++q)
        if (g.guides(q)) pdf[q] = a * guide_density(sc, g, q, l + 3 * q) + (1.0f - a) * pdf[q];
}

// cache-guided, before BRDF sampling: each guided point's strategy from its pick uniform
// (the guide below cache.guide), the uniform rescaled to [0, 1) for the choice made with it
// (the guide's texel, or the BRDF's own lobe).
template <class W>
inline void guided_picks(const W& w) {
    PathScratch& sc = w.scratch;
    CacheState& cache = cache_state(sc);
    GuideChoices& choices = cache.guide_choices;
    const size_t np = sc.sorted.size();
    choices.chose_guide.assign(np, 0);
    choices.guide_pick.assign(np, 0.0f);
    if (!guided_here(sc)) return;
    const float a = guide_probability(cache.guides, w.settings.cache);
    float* pick = sc.u_pick.data();
    for (size_t q = 0; q < np; ++q) {
        if (!cache.guides.guides(q)) continue;
        if (pick[q] < a) {
            choices.chose_guide[q] = 1;
            choices.guide_pick[q] = std::min(pick[q] / a, 0x1.fffffep-1f);
        } else {
            pick[q] = std::min((pick[q] - a) / (1.0f - a), 0x1.fffffep-1f);
        }
    }
}

// cache-guided, after BRDF sampling: the guide's directions for the points that chose it,
// then for every guided point the BRDF value and the mixture's density.
template <class W>
inline void guided_directions(const W& w) {
    PathScratch& sc = w.scratch;
    CacheState& cache = cache_state(sc);
    if (!guided_here(sc)) return;
    const GuidePool& g = cache.guides;
    const GuideChoices& choices = cache.guide_choices;
    const int R = g.resolution;
    const size_t T = static_cast<size_t>(R) * R, np = sc.sorted.size();
    const float a = guide_probability(g, w.settings.cache);
    float* ll = sc.l_local.data();
    bool any = false;
    for (size_t q = 0; q < np; ++q) {
        if (!g.guides(q)) continue;
        any = true;
        if (!choices.chose_guide[q]) continue;
        const int32_t p = g.cache_point_of[q];
        Vec3f d;
        if (p >= 0)
            d = pool_guide_sample(*g.points[p], g.cdf.data() + static_cast<size_t>(p) * T, R, choices.guide_pick[q], sc.u1[q],
                                  sc.u2[q]);
        else {
            float dir[3];
            g.field->sample(g.field_of[q], sc.u1[q], sc.u2[q], dir);
            d = Vec3f{dir[0], dir[1], dir[2]};
        }
        const ShadingPoint& sp = sc.sorted[q];
        ll[3 * q] = dot(d, sp.t), ll[3 * q + 1] = dot(d, sp.b), ll[3 * q + 2] = dot(d, sp.n);
    }
    if (!any) return;
    const float* vl = sc.v_local.data();
    const float* eta = sc.eta.data();
    float* fv = sc.bsdf_rgb.data();
    float* pdf = sc.pdf.data();
    for (size_t k = 0; k < w.scene.materials.size(); ++k) {
        const size_t b = sc.material_start[k], count = sc.material_start[k + 1] - b;
        bool guided = false;
        for (size_t q = b; q < b + count && !guided; ++q) guided = g.guides(q);
        if (!guided) continue;
        const Material& m = w.scene.materials[k];
        render_detail::material_eval(m, ll + 3 * b, vl + 3 * b, eta + b, fv + 3 * b, count);
        render_detail::material_pdf(m, ll + 3 * b, vl + 3 * b, eta + b, pdf + b, count);
    }
    for (size_t q = 0; q < np; ++q)
        if (g.guides(q)) pdf[q] = a * guide_density(sc, g, q, ll + 3 * q) + (1.0f - a) * pdf[q];
}

}  // namespace cache
PATINA_END_TARGET
