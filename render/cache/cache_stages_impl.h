// The radiance cache's stages in the wavefront integrator (integrator_impl.h calls them at
// the first hit; docs/radiance-cache.md), compiled once per width. Templates over the
// integrator's Wavefront, whose stages they sit between, and over its path tracer for the
// cache's own rays.
//   cache         add_cached_indirect: each first-hit point's hemisphere reconstructed
//                 (holes traced), integrated against its BRDF N texels at a time -- or, for
//                 a lobe too narrow for the texels (a clear coat, a near-mirror), by
//                 kLookupSamples BRDF samples looked up in the texture; the path then only
//                 looks for emission at its next hit (the direct light's BRDF-sampling half)
//   cache-guided  build_guides: each first-hit point's reconstructed radiance (holes at the
//                 mean: no rays) times its BRDF and cosine as a distribution over texels; the
//                 first bounce draws from it with probability cache.guide, else from the
//                 BRDF, its density the mixture's (one-sample MIS), so the estimate stays
//                 unbiased; light samples at that point weigh against the same mixture
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/constants.h"
#include "core/simd/kernel_width.h"
#include "core/vec3.h"
#include "render/cache/error_criterion.h"
#include "render/cache/hemisphere.h"
#include "render/cache/radiance_cache_impl.h"
#include "render/integrator.h"
#include "render/material_impl.h"
#include "render/rng.h"
#include "render/scene.h"

PATINA_BEGIN_TARGET
namespace cache {
using namespace kernel_width;

constexpr int kLookupSamples = 32;

// Whether the material's lobes are wide enough to be integrated over the texels (each about
// sqrt(2 pi) / R radians across): at least two texels wide, and no clear coat.
inline bool texel_resolvable(const Material& m, int resolution) {
    if (m.coat) return false;
    const float texel = 2.5066283f / static_cast<float>(resolution);
    switch (m.kind) {
        case MaterialKind::Lambert:
            return true;
        case MaterialKind::Conductor:
            return std::min(m.alpha_x, m.alpha_y) >= 2 * texel;
        case MaterialKind::Table:
        case MaterialKind::Mixture:
            return m.proxy_alpha >= 2 * texel;
        default:
            return false;
    }
}

// The texel of local direction l (z > 0) in an R x R hemisphere.
inline int32_t texel_of(float x, float y, float z, int R) {
    float u, v;
    hemisphere_to_square(x, y, z, u, v);
    const int i = std::min(std::max(static_cast<int>(u * R), 0), R - 1);
    const int j = std::min(std::max(static_cast<int>(v * R), 0), R - 1);
    return j * R + i;
}

// The guide's density (solid angle) at local direction l; cdf holds R^2 cumulative
// probabilities ending at 1.
inline float guide_pdf(const float* cdf, int R, const float* l) {
    if (!(l[2] > 0)) return 0.0f;
    const int32_t t = texel_of(l[0], l[1], l[2], R);
    const float p = cdf[t] - (t > 0 ? cdf[t - 1] : 0.0f);
    return p * static_cast<float>(R * R) / (2.0f * kPi);
}

// A direction drawn from the guide: the texel by `pick`, the point in it by (u1, u2).
inline void guide_sample(const float* cdf, int R, float pick, float u1, float u2, float* l) {
    const int T = R * R;
    int32_t t = static_cast<int32_t>(std::upper_bound(cdf, cdf + T, pick) - cdf);
    t = std::min(t, T - 1);
    while (t > 0 && !(cdf[t] > cdf[t - 1])) --t;  // never a texel of zero probability
    const float u = (static_cast<float>(t % R) + u1) / R, v = (static_cast<float>(t / R) + u2) / R;
    square_to_hemisphere(u, v, l[0], l[1], l[2]);
}

// Points of one pixel share a query (a reconstructed hemisphere and its integral) when
// they have the same material, normals within this cosine and the one within this many
// pixel footprints (at its distance from the camera) of the other's tangent plane (so a
// slanted wall's samples share, a parallel surface behind does not): the pixel's samples
// then cost the cache once, not once each, while its direct light is sampled at every one.
constexpr float kShareCos = 0.95f, kSharePixels = 2.0f;

// The first-hit points the cache serves, as queries: one per pixel and surface
// (st.query_point: the point whose hemisphere it is; st.query_of: each point's query or -1).
template <class W, class Accept>
inline size_t collect_queries(const W& w, CacheState& st, Accept accept) {
    const PathScratch& sc = w.sc;
    const size_t np = sc.sorted.size();
    st.queries.clear();
    st.query_point.clear();
    st.query_of.assign(np, -1);
    st.pixel_query.clear();
    for (size_t k = 0; k < w.s.materials.size(); ++k) {
        if (!accept(w.s.materials[k])) continue;
        st.pixel_query.clear();  // per material
        const size_t first = sc.material_start[k], last = sc.material_start[k + 1];
        for (size_t q = first; q < last; ++q) {
            const ShadingPoint& sp = sc.sorted[q];
            const CameraSample& c = w.cs[sp.path];
            const int64_t pixel = static_cast<int64_t>(std::floor(c.fy)) * w.s.camera.width + static_cast<int64_t>(std::floor(c.fx));
            const Camera& cam = w.s.camera;
            const float footprint = w.out[sp.path].depth * 2.0f * cam.tan_half_fov / static_cast<float>(cam.height);
            auto found = st.pixel_query.find(pixel);
            if (found != st.pixel_query.end()) {
                const ShadingPoint& rep = sc.sorted[st.query_point[found->second]];
                const float off_plane = std::abs(dot(rep.n, sp.p - rep.p));
                if (dot(sp.n, rep.n) >= kShareCos && off_plane <= kSharePixels * footprint) {
                    st.query_of[q] = found->second;
                    continue;
                }
            }
            const int32_t qi = static_cast<int32_t>(st.queries.size());
            // the sample's own key (the stream key is the pixel's, shared by its samples)
            const uint32_t key = sample_key(static_cast<uint32_t>(sc.point_keys[q]), static_cast<uint32_t>(sc.point_index[q]));
            st.queries.push_back(Query{sp.p, sp.ng, sp.t, sp.b, sp.n, key,
                                       kMinReusePixels * footprint / w.st.cache.error});
            st.query_point.push_back(static_cast<int32_t>(q));
            st.query_of[q] = qi;
            if (found == st.pixel_query.end()) st.pixel_query.emplace(pixel, qi);
        }
    }
    return st.queries.size();
}

// f(l_t, v) at the texels [0, n) listed in st.l for the point's view v (st.f, RGB).
inline void eval_at_texels(const Material& m, const float* v, float eta, CacheState& st, size_t n) {
    float* vv = grow(st.v, 3 * n);
    float* ee = grow(st.eta, n);
    for (size_t k = 0; k < n; ++k) std::copy(v, v + 3, vv + 3 * k), ee[k] = eta;
    render_detail::material_eval(m, st.l.data(), vv, ee, grow(st.f, 3 * n), n);
}

template <class W>
inline void add_counts(const W& w, const CacheCounts& c, const CacheState& st, size_t rays_before) {
    w.sc.cache_points += c.points;
    w.sc.cache_queries += c.queries;
    w.sc.cache_texels_reprojected += c.reprojected + c.from_misses;
    w.sc.cache_texels_traced += c.traced;
    w.sc.rays_traced += st.inner.rays_traced - rays_before;
}

// cache: the indirect light of every first-hit point but glass, from the cache.
template <class W, class Tracer>
inline void add_cached_indirect(const W& w, Tracer& trace) {
    PathScratch& sc = w.sc;
    CacheState& st = cache_state(sc);
    const CacheSettings& cfg = w.st.cache;
    const int R = cfg.resolution;
    const size_t T = static_cast<size_t>(R) * R;
    const float texel = texel_solid_angle(R);
    const size_t n = collect_queries(w, st, [](const Material& m) { return m.kind != MaterialKind::Dielectric; });
    const size_t rays_before = st.inner.rays_traced;
    st.dirs.prepare(R);
    auto consume = [&](size_t qi, const float* radiance) {
        const size_t q = st.query_point[qi];
        const ShadingPoint& sp = sc.sorted[q];
        const Material& m = w.s.materials[sp.material];
        const float* v = sc.v_local.data() + 3 * q;
        double sum[3] = {0, 0, 0};
        if (texel_resolvable(m, R)) {
            // the texels with light, N at a time through the BRDF
            float* l = grow(st.l, 3 * T);
            float* rgb = grow(st.rgb, 3 * T);
            size_t count = 0;
            for (size_t t = 0; t < T; ++t) {
                const float* L = radiance + 3 * t;
                if (!(L[0] > 0 || L[1] > 0 || L[2] > 0)) continue;
                l[3 * count] = st.dirs.x[t], l[3 * count + 1] = st.dirs.y[t], l[3 * count + 2] = st.dirs.z[t];
                std::copy(L, L + 3, rgb + 3 * count);
                ++count;
            }
            if (count > 0) {
                eval_at_texels(m, v, sc.eta[q], st, count);
                for (size_t k = 0; k < count; ++k)
                    for (int c = 0; c < 3; ++c)
                        sum[c] += static_cast<double>(st.f[3 * k + c]) * rgb[3 * k + c] * l[3 * k + 2];
            }
            for (double& s : sum) s *= texel;
        } else {
            // a narrow lobe: its own importance sampling, the radiance looked up in the texture
            const size_t K = kLookupSamples;
            float* vv = grow(st.v, 3 * K);
            float* ee = grow(st.eta, K);
            float* u0 = grow(st.u0, K);
            float* u1 = grow(st.u1, K);
            float* u2 = grow(st.u2, K);
            const uint32_t key = hash_u32(st.queries[qi].key ^ 0x2545f491u);
            for (size_t k = 0; k < K; ++k) {
                std::copy(v, v + 3, vv + 3 * k);
                ee[k] = sc.eta[q];
                u0[k] = uniform(key, 3 * static_cast<uint32_t>(k));
                u1[k] = uniform(key, 3 * static_cast<uint32_t>(k) + 1);
                u2[k] = uniform(key, 3 * static_cast<uint32_t>(k) + 2);
            }
            float* l = grow(st.l, 3 * K);
            float* pdf = grow(st.pdf, K);
            render_detail::material_sample(m, vv, ee, u0, u1, u2, l, pdf, K);
            render_detail::material_eval(m, l, vv, ee, grow(st.f, 3 * K), K);
            for (size_t k = 0; k < K; ++k) {
                const float* d = l + 3 * k;
                if (!(pdf[k] > 0) || !(d[2] > 0)) continue;
                const float* L = radiance + 3 * texel_of(d[0], d[1], d[2], R);
                for (int c = 0; c < 3; ++c) sum[c] += static_cast<double>(st.f[3 * k + c]) * d[2] / pdf[k] * L[c];
            }
            for (double& s : sum) s /= static_cast<double>(K);
        }
        for (int c = 0; c < 3; ++c) st.sums[3 * qi + c] = static_cast<float>(sum[c]);
    };
    st.sums.assign(3 * n, 0.0f);
    const CacheCounts c = reconstruct_hemispheres(cfg, w.eps, st.queries.data(), n, true, st, trace, consume);
    add_counts(w, c, st, rays_before);
    // every point of a query: its indirect light
    for (size_t q = 0; q < sc.sorted.size(); ++q) {
        if (st.query_of[q] < 0) continue;
        const int32_t path = sc.sorted[q].path;
        const float* Tp = sc.throughput.data() + 3 * path;
        for (int k = 0; k < 3; ++k) w.out[path].rgb[k] += Tp[k] * st.sums[3 * st.query_of[q] + k];
        sc.cached[path] = 1;
    }
}

// cache-guided: a guide (an R^2 cdf in sc.guide_cdf) for every first-hit point whose lobes
// the texels resolve.
template <class W, class Tracer>
inline void build_guides(const W& w, Tracer& trace) {
    PathScratch& sc = w.sc;
    CacheState& st = cache_state(sc);
    const CacheSettings& cfg = w.st.cache;
    const int R = cfg.resolution;
    const size_t T = static_cast<size_t>(R) * R;
    sc.guide_of.assign(sc.sorted.size(), -1);
    const size_t n = collect_queries(w, st, [&](const Material& m) { return texel_resolvable(m, R); });
    float* cdf = grow(sc.guide_cdf, n * T);
    const size_t rays_before = st.inner.rays_traced;
    st.dirs.prepare(R);
    float* l = grow(st.l, 3 * T);
    for (size_t t = 0; t < T; ++t) l[3 * t] = st.dirs.x[t], l[3 * t + 1] = st.dirs.y[t], l[3 * t + 2] = st.dirs.z[t];
    auto consume = [&](size_t qi, const float* radiance) {
        const size_t q = st.query_point[qi];
        const ShadingPoint& sp = sc.sorted[q];
        eval_at_texels(w.s.materials[sp.material], sc.v_local.data() + 3 * q, sc.eta[q], st, T);
        float* c = cdf + qi * T;
        double acc = 0;
        for (size_t t = 0; t < T; ++t) {
            float prod[3];
            for (int k = 0; k < 3; ++k) prod[k] = radiance[3 * t + k] * st.f[3 * t + k];
            acc += std::max(0.0f, luminance(prod)) * l[3 * t + 2];
            c[t] = static_cast<float>(acc);
        }
        if (!(acc > 0) || !std::isfinite(acc)) return;
        const float inv = static_cast<float>(1.0 / acc);
        for (size_t t = 0; t < T; ++t) c[t] *= inv;
        c[T - 1] = 1.0f;
        sc.guide_of[q] = static_cast<int32_t>(qi);
    };
    const CacheCounts counts = reconstruct_hemispheres(cfg, w.eps, st.queries.data(), n, false, st, trace, consume);
    add_counts(w, counts, st, rays_before);
    // the other points of a query draw from its guide (in their own frames: another
    // distribution, as valid, its density evaluated the same way)
    for (size_t q = 0; q < sc.sorted.size(); ++q)
        if (st.query_of[q] >= 0) sc.guide_of[q] = sc.guide_of[st.query_point[st.query_of[q]]];
}

inline bool has_guides(const PathScratch& sc);

// cache-guided, light sampling at the first hit: the BRDF-sampling density the light
// sample's MIS weight compares with is the mixture's.
inline void mix_light_pdfs(const PathScratch& sc, const CacheSettings& cfg, const float* l, float* pdf, size_t n) {
    if (!has_guides(sc)) return;
    const int R = cfg.resolution;
    const size_t T = static_cast<size_t>(R) * R;
    for (size_t q = 0; q < n; ++q) {
        if (sc.guide_of[q] < 0) continue;
        const float g = guide_pdf(sc.guide_cdf.data() + sc.guide_of[q] * T, R, l + 3 * q);
        pdf[q] = cfg.guide * g + (1.0f - cfg.guide) * pdf[q];
    }
}

// Whether this bounce's points have guides (cache-guided at the first hit, built by build_guides).
inline bool has_guides(const PathScratch& sc) { return sc.guide_of.size() == sc.sorted.size(); }

// cache-guided, before BRDF sampling at the first hit: each guided point's strategy from its
// pick uniform (the guide below cache.guide), the uniform rescaled to [0, 1) for the choice
// made with it (the guide's texel, or the BRDF's own lobe).
template <class W>
inline void guided_picks(const W& w) {
    PathScratch& sc = w.sc;
    CacheState& st = cache_state(sc);
    const size_t np = sc.sorted.size();
    st.chose_guide.assign(np, 0);
    st.guide_pick.assign(np, 0.0f);
    if (!has_guides(sc)) return;
    const float a = w.st.cache.guide;
    float* pick = sc.u_pick.data();
    for (size_t q = 0; q < np; ++q) {
        if (sc.guide_of[q] < 0) continue;
        if (pick[q] < a) {
            st.chose_guide[q] = 1;
            st.guide_pick[q] = std::min(pick[q] / a, 0x1.fffffep-1f);
        } else {
            pick[q] = std::min((pick[q] - a) / (1.0f - a), 0x1.fffffep-1f);
        }
    }
}

// cache-guided, after BRDF sampling at the first hit: the guide's directions for the points
// that chose it, then for every guided point the BRDF value and the mixture's density.
template <class W>
inline void guided_directions(const W& w) {
    PathScratch& sc = w.sc;
    CacheState& st = cache_state(sc);
    if (!has_guides(sc)) return;
    const int R = w.st.cache.resolution;
    const size_t T = static_cast<size_t>(R) * R, np = sc.sorted.size();
    const float a = w.st.cache.guide;
    float* ll = sc.l_local.data();
    bool any = false;
    for (size_t q = 0; q < np; ++q) {
        if (sc.guide_of[q] < 0) continue;
        any = true;
        if (st.chose_guide[q])
            guide_sample(sc.guide_cdf.data() + sc.guide_of[q] * T, R, st.guide_pick[q], sc.u1[q], sc.u2[q], ll + 3 * q);
    }
    if (!any) return;
    const float* vl = sc.v_local.data();
    const float* eta = sc.eta.data();
    float* fv = sc.f.data();
    float* pdf = sc.pdf.data();
    for (size_t k = 0; k < w.s.materials.size(); ++k) {
        const size_t b = sc.material_start[k], count = sc.material_start[k + 1] - b;
        bool guided = false;
        for (size_t q = b; q < b + count && !guided; ++q) guided = sc.guide_of[q] >= 0;
        if (!guided) continue;
        const Material& m = w.s.materials[k];
        render_detail::material_eval(m, ll + 3 * b, vl + 3 * b, eta + b, fv + 3 * b, count);
        render_detail::material_pdf(m, ll + 3 * b, vl + 3 * b, eta + b, pdf + b, count);
    }
    for (size_t q = 0; q < np; ++q) {
        if (sc.guide_of[q] < 0) continue;
        const float g = guide_pdf(sc.guide_cdf.data() + sc.guide_of[q] * T, R, ll + 3 * q);
        pdf[q] = a * g + (1.0f - a) * pdf[q];
    }
}

}  // namespace cache
PATINA_END_TARGET
