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
inline bool cache_points_guide(const PathScratch& scratch, const CacheSettings& cfg) {
    return scratch.guide_sink == nullptr && cfg.train_passes == 0;
}

// cache-guided, at the first hit: the cache points this batch's guides come from -- the
// shared points, and points of its own for the first hits (queries, as `cache` makes them)
// that none of those serves.
template <class W, class Tracer>
inline void place_guide_points(const W& wavefront, Tracer& trace) {
    if (!cache_points_guide(wavefront.scratch, wavefront.settings.cache)) return;
    CacheState& cache = start_cache_stage(wavefront);
    const size_t rays_before = cache.inner.rays_traced;
    const std::vector<Query>& queries = cache.table.queries;
    place_cache_points(wavefront.settings.cache, wavefront.ray_offset, queries.data(), queries.size(), cache, trace);
    wavefront.scratch.cache_points += cache.build.used;
    wavefront.scratch.cache_queries += cache.table.queries.size();
    wavefront.scratch.rays_traced += cache.inner.rays_traced - rays_before;
    if (cache.build.pool.empty())  // no queries: the shared points alone
        for (const CachePoint* a : wavefront.scratch.cache_shared) cache.build.pool.push_back(a);
    cache.guides.prepare(cache.build.pool, wavefront.settings.cache.resolution);
    cache.lap(Stage::CachePlace);
}

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
// first cache.guide_bounces bounces (default 1, the first hit's) its cache point
// (cache.guides.cache_point_of) where the cache points guide, for the materials whose lobes
// the texels resolve; else, at the first cache.train_bounces bounces, its trained guide's
// distribution (cache.guides.field_of), for the materials field_guidable takes. A later
// vertex takes the batch's cache point of least error as a first hit does: the points near
// the tile's first hits, so a vertex far from all of them is its BRDF's alone. Guiding the
// later bounces did not pay on the bundled scenes (docs/radiance-cache.md, "Guiding every
// bounce": a later vertex's light is less like any cache point's, whose texels hold the
// direct light at their hits), hence the default.
template <class W>
inline void assign_guides(const W& wavefront, int depth) {
    PathScratch& scratch = wavefront.scratch;
    CacheState& cache = cache_state(scratch);
    GuidePool& pool = cache.guides;
    const int R = wavefront.settings.cache.resolution;
    const size_t np = scratch.sorted.size();
    pool.cache_point_of.assign(np, -1);
    pool.field_of.assign(np, -1);
    pool.any = false;
    pool.field = scratch.guide_field;
    if (depth < wavefront.settings.cache.guide_bounces && !pool.points.empty() && pool.resolution == R) {
        cache.texel_directions.prepare(R);
        for (size_t k = 0; k < wavefront.scene.materials.size(); ++k) {
            if (!texel_resolvable(wavefront.scene.materials[k], R)) continue;
            const size_t first = scratch.material_start[k], last = scratch.material_start[k + 1];
            for (size_t q = first; q < last; ++q) {
                const ShadingPoint& sp = scratch.sorted[q];
                const int32_t a = pool.find(sp.p, sp.n);
                if (a >= 0 && pool.guide(a, cache.texel_directions)) pool.cache_point_of[q] = a, pool.any = true;
            }
        }
    }
    if (pool.field != nullptr && !pool.field->empty() && depth < wavefront.settings.cache.train_bounces)
        for (size_t k = 0; k < wavefront.scene.materials.size(); ++k) {
            if (!field_guidable(wavefront.scene.materials[k])) continue;
            const size_t first = scratch.material_start[k], last = scratch.material_start[k + 1];
            for (size_t q = first; q < last; ++q) {
                if (pool.cache_point_of[q] >= 0) continue;
                const ShadingPoint& sp = scratch.sorted[q];
                const float at[3] = {sp.p.x, sp.p.y, sp.p.z}, n[3] = {sp.n.x, sp.n.y, sp.n.z};
                pool.field_of[q] = pool.field->distribution_at(at, n);
                pool.any = pool.any || pool.field_of[q] >= 0;
            }
        }
    scratch.timer.lap(Stage::CacheIntegrate);
}

// The probability of the guide's strategy in the mixture: cache.guide for the cache points',
// cache.train_guide for the trained guide's (one a bounce: the two never guide one bounce).
inline float guide_probability(const GuidePool& pool, const CacheSettings& cfg) {
    return pool.field != nullptr ? cfg.train_guide : cfg.guide;
}

inline bool guided_here(const PathScratch& scratch) {
    if (!scratch.cache) return false;
    const GuidePool& pool = static_cast<const CacheState*>(scratch.cache.get())->guides;
    return pool.any && pool.cache_point_of.size() == scratch.sorted.size();
}

// The guide's density at point q's local direction l (0 without a guide).
inline float guide_density(const PathScratch& scratch, const GuidePool& pool, size_t q, const float* l) {
    const int32_t a = pool.cache_point_of[q];
    if (a < 0 && pool.field_of[q] < 0) return 0.0f;
    const ShadingPoint& sp = scratch.sorted[q];
    const Vec3f d = l[0] * sp.t + l[1] * sp.b + l[2] * sp.n;
    if (a < 0) {
        const Vec3f u = normalize(d);
        const float dir[3] = {u.x, u.y, u.z};
        return pool.field->pdf(pool.field_of[q], dir);
    }
    const size_t texel_count = static_cast<size_t>(pool.resolution) * pool.resolution;
    return pool_guide_pdf(*pool.points[a], pool.cdf.data() + static_cast<size_t>(a) * texel_count, pool.resolution, d);
}

// cache-guided, light sampling: the BRDF-sampling density each light sample's MIS weight
// compares with is the mixture's at the guided points.
inline void mix_light_pdfs(const PathScratch& scratch, const CacheSettings& cfg, const float* l, float* pdf, size_t n) {
    if (!guided_here(scratch)) return;
    const GuidePool& pool = static_cast<const CacheState*>(scratch.cache.get())->guides;
    const float a = guide_probability(pool, cfg);
    for (size_t q = 0; q < n; ++q)
        if (pool.guides(q)) pdf[q] = a * guide_density(scratch, pool, q, l + 3 * q) + (1.0f - a) * pdf[q];
}

// cache-guided, before BRDF sampling: each guided point's strategy from its pick uniform
// (the guide below cache.guide), the uniform rescaled to [0, 1) for the choice made with it
// (the guide's texel, or the BRDF's own lobe).
template <class W>
inline void guided_picks(const W& wavefront) {
    PathScratch& scratch = wavefront.scratch;
    CacheState& cache = cache_state(scratch);
    GuideChoices& choices = cache.guide_choices;
    const size_t np = scratch.sorted.size();
    choices.chose_guide.assign(np, 0);
    choices.guide_pick.assign(np, 0.0f);
    if (!guided_here(scratch)) return;
    const float a = guide_probability(cache.guides, wavefront.settings.cache);
    float* pick = scratch.u_pick.data();
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
inline void guided_directions(const W& wavefront) {
    PathScratch& scratch = wavefront.scratch;
    CacheState& cache = cache_state(scratch);
    if (!guided_here(scratch)) return;
    const GuidePool& pool = cache.guides;
    const GuideChoices& choices = cache.guide_choices;
    const int R = pool.resolution;
    const size_t texel_count = static_cast<size_t>(R) * R, np = scratch.sorted.size();
    const float a = guide_probability(pool, wavefront.settings.cache);
    float* ll = scratch.l_local.data();
    bool any = false;
    for (size_t q = 0; q < np; ++q) {
        if (!pool.guides(q)) continue;
        any = true;
        if (!choices.chose_guide[q]) continue;
        const int32_t p = pool.cache_point_of[q];
        Vec3f d;
        if (p >= 0)
            d = pool_guide_sample(*pool.points[p], pool.cdf.data() + static_cast<size_t>(p) * texel_count, R,
                                  choices.guide_pick[q], scratch.uniform_u[q], scratch.uniform_v[q]);
        else {
            float dir[3];
            pool.field->sample(pool.field_of[q], scratch.uniform_u[q], scratch.uniform_v[q], dir);
            d = Vec3f{dir[0], dir[1], dir[2]};
        }
        const ShadingPoint& sp = scratch.sorted[q];
        ll[3 * q] = dot(d, sp.t), ll[3 * q + 1] = dot(d, sp.b), ll[3 * q + 2] = dot(d, sp.n);
    }
    if (!any) return;
    const float* vl = scratch.v_local.data();
    const float* eta = scratch.eta.data();
    float* fv = scratch.bsdf_rgb.data();
    float* pdf = scratch.pdf.data();
    for (size_t k = 0; k < wavefront.scene.materials.size(); ++k) {
        const size_t b = scratch.material_start[k], count = scratch.material_start[k + 1] - b;
        bool guided = false;
        for (size_t q = b; q < b + count && !guided; ++q) guided = pool.guides(q);
        if (!guided) continue;
        const Material& m = wavefront.scene.materials[k];
        render_detail::material_eval(m, ll + 3 * b, vl + 3 * b, eta + b, fv + 3 * b, count);
        render_detail::material_pdf(m, ll + 3 * b, vl + 3 * b, eta + b, pdf + b, count);
    }
    for (size_t q = 0; q < np; ++q)
        if (pool.guides(q)) pdf[q] = a * guide_density(scratch, pool, q, ll + 3 * q) + (1.0f - a) * pdf[q];
}

}  // namespace cache
PATINA_END_TARGET
