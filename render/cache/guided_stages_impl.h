// cache-guided's stages in the wavefront integrator (integrator_impl.h calls them), compiled
// once per width: at the first hit the batch's cache points (the regions' shared points,
// and points of its own for first hits none of them serves: place_cache_points), then at
// the guided bounces each shading point's guide (guided_bounces_impl.h), the light
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
#include "render/integrator.h"
#include "render/material_impl.h"

PATINA_BEGIN_TARGET
namespace cache {

// cache-guided, at the first hit: the cache points this batch's guides come from -- the
// shared points, and points of its own for the first hits (queries, as `cache` makes them)
// that none of those serves.
template <class W, class Tracer>
inline void place_guide_points(const W& w, Tracer& trace) {
    CacheState& st = start_cache_stage(w);
    const size_t rays_before = st.inner.rays_traced;
    place_cache_points(w.st.cache, w.eps, st.queries.data(), st.queries.size(), st, trace);
    w.sc.cache_points += st.used;
    w.sc.cache_queries += st.queries.size();
    w.sc.rays_traced += st.inner.rays_traced - rays_before;
    if (st.pool.empty())  // no queries: the shared points alone
        for (const CachePoint* a : w.sc.cache_shared) st.pool.push_back(a);
    st.guides.prepare(st.pool, w.st.cache.resolution);
    st.lap(Stage::CachePlace);
}

// The bounces cache-guided guides: the first hit's. Guiding every bounce from the same
// points (the later vertices' nearest cache point, the tile's regions and their
// neighbours') was measured on the bundled scenes at 64 pixels wide, 16 spp: the room's
// variance fell 23 %, the studio's and the IES interior's rose 39 and 51 %, as the later
// vertices' light is less like any cache point's; the first hit alone: -17 %, +15 %, +17 %
// at less cost.
constexpr int kGuidedBounces = 1;

// cache-guided, at the guided bounces before light sampling: each shading point's guide
// point (st.guides.of), for the materials whose lobes the texels resolve.
template <class W>
inline void assign_guides(const W& w, int depth) {
    PathScratch& sc = w.sc;
    CacheState& st = cache_state(sc);
    GuidePool& g = st.guides;
    const int R = w.st.cache.resolution;
    g.of.assign(sc.sorted.size(), -1);
    if (depth >= kGuidedBounces) return;
    if (g.points.empty() || g.resolution != R) return;
    st.dirs.prepare(R);
    for (size_t k = 0; k < w.s.materials.size(); ++k) {
        if (!texel_resolvable(w.s.materials[k], R)) continue;
        const size_t first = sc.material_start[k], last = sc.material_start[k + 1];
        for (size_t q = first; q < last; ++q) {
            const ShadingPoint& sp = sc.sorted[q];
            const int32_t a = g.find(sp.p, sp.n);
            if (a >= 0 && g.guide(a, st.dirs)) g.of[q] = a;
        }
    }
    sc.timer.lap(Stage::CacheIntegrate);
}

inline bool guided_here(const PathScratch& sc) {
    if (!sc.cache) return false;
    const GuidePool& g = static_cast<const CacheState*>(sc.cache.get())->guides;
    return g.of.size() == sc.sorted.size() && !g.points.empty();
}

// The guide's density at point q's local direction l (0 without a guide).
inline float guide_density(const PathScratch& sc, const GuidePool& g, size_t q, const float* l) {
    const int32_t a = g.of[q];
    if (a < 0) return 0.0f;
    const ShadingPoint& sp = sc.sorted[q];
    const Vec3f d = l[0] * sp.t + l[1] * sp.b + l[2] * sp.n;
    const size_t T = static_cast<size_t>(g.resolution) * g.resolution;
    return pool_guide_pdf(*g.points[a], g.cdf.data() + static_cast<size_t>(a) * T, g.resolution, d);
}

// cache-guided, light sampling: the BRDF-sampling density each light sample's MIS weight
// compares with is the mixture's at the guided points.
inline void mix_light_pdfs(const PathScratch& sc, const CacheSettings& cfg, const float* l, float* pdf, size_t n) {
    if (!guided_here(sc)) return;
    const GuidePool& g = static_cast<const CacheState*>(sc.cache.get())->guides;
    for (size_t q = 0; q < n; ++q)
        if (g.of[q] >= 0) pdf[q] = cfg.guide * guide_density(sc, g, q, l + 3 * q) + (1.0f - cfg.guide) * pdf[q];
}

// cache-guided, before BRDF sampling: each guided point's strategy from its pick uniform
// (the guide below cache.guide), the uniform rescaled to [0, 1) for the choice made with it
// (the guide's texel, or the BRDF's own lobe).
template <class W>
inline void guided_picks(const W& w) {
    PathScratch& sc = w.sc;
    CacheState& st = cache_state(sc);
    const size_t np = sc.sorted.size();
    st.chose_guide.assign(np, 0);
    st.guide_pick.assign(np, 0.0f);
    if (!guided_here(sc)) return;
    const float a = w.st.cache.guide;
    float* pick = sc.u_pick.data();
    for (size_t q = 0; q < np; ++q) {
        if (st.guides.of[q] < 0) continue;
        if (pick[q] < a) {
            st.chose_guide[q] = 1;
            st.guide_pick[q] = std::min(pick[q] / a, 0x1.fffffep-1f);
        } else {
            pick[q] = std::min((pick[q] - a) / (1.0f - a), 0x1.fffffep-1f);
        }
    }
}

// cache-guided, after BRDF sampling: the guide's directions for the points that chose it,
// then for every guided point the BRDF value and the mixture's density.
template <class W>
inline void guided_directions(const W& w) {
    PathScratch& sc = w.sc;
    CacheState& st = cache_state(sc);
    if (!guided_here(sc)) return;
    const GuidePool& g = st.guides;
    const int R = g.resolution;
    const size_t T = static_cast<size_t>(R) * R, np = sc.sorted.size();
    const float a = w.st.cache.guide;
    float* ll = sc.l_local.data();
    bool any = false;
    for (size_t q = 0; q < np; ++q) {
        const int32_t p = g.of[q];
        if (p < 0) continue;
        any = true;
        if (!st.chose_guide[q]) continue;
        const Vec3f d = pool_guide_sample(*g.points[p], g.cdf.data() + static_cast<size_t>(p) * T, R,
                                          st.guide_pick[q], sc.u1[q], sc.u2[q]);
        const ShadingPoint& sp = sc.sorted[q];
        ll[3 * q] = dot(d, sp.t), ll[3 * q + 1] = dot(d, sp.b), ll[3 * q + 2] = dot(d, sp.n);
    }
    if (!any) return;
    const float* vl = sc.v_local.data();
    const float* eta = sc.eta.data();
    float* fv = sc.f.data();
    float* pdf = sc.pdf.data();
    for (size_t k = 0; k < w.s.materials.size(); ++k) {
        const size_t b = sc.material_start[k], count = sc.material_start[k + 1] - b;
        bool guided = false;
        for (size_t q = b; q < b + count && !guided; ++q) guided = g.of[q] >= 0;
        if (!guided) continue;
        const Material& m = w.s.materials[k];
        render_detail::material_eval(m, ll + 3 * b, vl + 3 * b, eta + b, fv + 3 * b, count);
        render_detail::material_pdf(m, ll + 3 * b, vl + 3 * b, eta + b, pdf + b, count);
    }
    for (size_t q = 0; q < np; ++q)
        if (g.of[q] >= 0) pdf[q] = a * guide_density(sc, g, q, ll + 3 * q) + (1.0f - a) * pdf[q];
}

}  // namespace cache
PATINA_END_TARGET
