// cache-guided's guides from cache points (docs/radiance-cache.md, "cache-guided"),
// compiled once per width. A shading point of a material whose lobes the texels resolve
// (texel_resolvable) takes the cache point of least reuse error (Ward's, error_criterion.h)
// within kGuideBound, its normal within acos kGuideCos, among the batch's cache points (the
// regions' shared points and the batch's own), and draws its next direction from that
// point's incident radiance x cosine -- in the cache point's own frame: a guide needs the
// shape of the light, not parallax-exact values, so nothing is reprojected and no BRDF is
// evaluated over the texels (the reprojection was most of the old guide's cost and the
// product with the BRDF lowered the variance no more, measured) -- with probability
// cache.guide, else from its BRDF; the density is the mixture's (one-sample MIS), and light
// samples at that point weigh against the same mixture, so the estimate stays unbiased:
// the BRDF's share covers every direction the guide gives no probability (under the cache
// point's horizon, a black texel).
//
// Which bounces are guided: cache.guide_bounces (guided_stages_impl.h). A cache point's guide
// is built once per batch, at its first use: a cdf over its texels (guided_distribution.h:
// the radiance averaged over cells, a floor under every texel). The points are found
// through a uniform grid of their reach (kGuideBound x reuse radius), so a lookup tests the
// few points whose reach holds the shading point.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/constants.h"
#include "core/simd/kernel_width.h"
#include "core/vec3.h"
#include "render/cache/cache_point.h"
#include "render/cache/error_criterion.h"
#include "render/cache/guided_distribution.h"
#include "render/cache/hemisphere.h"
#include "render/cache/reprojection_impl.h"
#include "render/guiding/guide_field.h"
#include "render/integrators/integrator.h"

PATINA_BEGIN_TARGET
namespace cache {

// The reuse error up to which a shading point is guided by a cache point: twice the
// default placement bound (cache.error 0.5). A guide from a point farther off is still
// unbiased, only less like the point's own light.
constexpr float kGuideBound = 1.0f;
// ... and whose normal is within acos kGuideCos of the shading point's: the guide lives on
// the cache point's hemisphere, and its directions under the shading point's horizon are
// samples wasted (their BRDF is zero).
constexpr float kGuideCos = 0.95f;

// The guides of one work item's shared cache points.
struct GuidePool {
    std::vector<const CachePoint*> points;  // the batch's cache points (none: no guides)
    int resolution = 0;
    std::vector<float> cdf;       // per point R^2 cumulative probabilities (when ready)
    std::vector<uint8_t> ready;   // 0: not built yet, 1: built, 2: no light (no guide)
    std::vector<float> cell;      // scratch of guide_cdf
    // the uniform grid: cell (i, j, k) of side cell_side holds the points whose reach meets it
    float cell_side = 0;
    std::unordered_map<int64_t, std::vector<int32_t>> grid;
    std::vector<int32_t> everywhere;  // points of unbounded reach (no hits: infinite radius)
    std::vector<int32_t> cache_point_of;  // per shading point of the bounce: its guide point, or -1
    // the trained guide (render/guiding/guide_field.h), where there is one: per shading point
    // of the bounce that no cache point guides, its field distribution, or -1
    const guiding::GuideField* field = nullptr;
    std::vector<int32_t> field_of;
    bool any = false;  // some point of the bounce is guided
    void clear() { points.clear(), cache_point_of.clear(), field_of.clear(), any = false; }
    bool guides(size_t q) const { return cache_point_of[q] >= 0 || field_of[q] >= 0; }

    static int64_t key(int64_t i, int64_t j, int64_t k) {
        return ((i & 0x1fffff) << 42) | ((j & 0x1fffff) << 21) | (k & 0x1fffff);
    }
    int64_t cell_of(float x) const { return static_cast<int64_t>(std::floor(x / cell_side)); }

    // Made for each batch (a batch's own cache points reuse the memory of the last one's).
    void prepare(const std::vector<const CachePoint*>& pool, int R) {
        points = pool;
        resolution = R;
        const size_t texel_count = static_cast<size_t>(R) * R;
        cdf.assign(points.size() * texel_count, 0.0f);
        ready.assign(points.size(), 0);
        grid.clear();
        everywhere.clear();
        std::vector<float> reach;
        for (const CachePoint* a : points)
            if (std::isfinite(a->reuse_radius)) reach.push_back(kGuideBound * a->reuse_radius);
        if (reach.empty()) {
            for (size_t a = 0; a < points.size(); ++a) everywhere.push_back(static_cast<int32_t>(a));
            return;
        }
        std::nth_element(reach.begin(), reach.begin() + reach.size() / 2, reach.end());
        cell_side = std::max(reach[reach.size() / 2], 1e-6f);
        for (size_t a = 0; a < points.size(); ++a) {
            const CachePoint& p = *points[a];
            const float r = kGuideBound * p.reuse_radius;
            // a reach of more than 8 cells a side is tested everywhere (few such points)
            if (!std::isfinite(r) || r > 8 * cell_side) {
                everywhere.push_back(static_cast<int32_t>(a));
                continue;
            }
            const int64_t x0 = cell_of(p.p.x - r), x1 = cell_of(p.p.x + r);
            const int64_t y0 = cell_of(p.p.y - r), y1 = cell_of(p.p.y + r);
            const int64_t z0 = cell_of(p.p.z - r), z1 = cell_of(p.p.z + r);
            for (int64_t i = x0; i <= x1; ++i)
                for (int64_t j = y0; j <= y1; ++j)
                    for (int64_t k = z0; k <= z1; ++k) grid[key(i, j, k)].push_back(static_cast<int32_t>(a));
        }
    }

    // The point of least reuse error within kGuideBound for a shading point at p with
    // normal n, or -1.
    int32_t find(const Vec3f& p, const Vec3f& n) const {
        int32_t best = -1;
        float best_error = kGuideBound;
        auto test = [&](int32_t a) {
            if (!(dot(points[a]->n, n) >= kGuideCos)) return;  // a guide for another hemisphere wastes samples
            const float e = reuse_error(*points[a], p, n);
            if (e <= best_error && (best < 0 || e < best_error || a < best)) best = a, best_error = e;
        };
        for (const int32_t a : everywhere) test(a);
        if (cell_side > 0) {
            const auto found = grid.find(key(cell_of(p.x), cell_of(p.y), cell_of(p.z)));
            if (found != grid.end())
                for (const int32_t a : found->second) test(a);
        }
        return best;
    }

    // Point a's cdf (built at its first use), or null when its texture holds no light.
    const float* guide(int32_t a, const TexelDirections& dirs) {
        const int R = resolution;
        const size_t texel_count = static_cast<size_t>(R) * R;
        float* c = cdf.data() + static_cast<size_t>(a) * texel_count;
        if (ready[a] == 0) {  // the radiance x the cosine in the point's own frame
            cell.resize(3 * texel_count);
            ready[a] = guide_cdf(points[a]->radiance.data(), dirs.z.data(), R, cell.data(), c) ? 1 : 2;
        }
        return ready[a] == 1 ? c : nullptr;
    }
};

// cache-guided, per shading point of the bounce before BRDF sampling (guided_picks,
// guided_stages_impl.h): whether it draws its direction from its guide, and the uniform that
// then picks the guide's texel (read by guided_directions).
struct GuideChoices {
    std::vector<uint8_t> chose_guide;
    std::vector<float> guide_pick;
};

// The density (solid angle) of cache point a's guide `cdf` at world direction d (unit).
inline float pool_guide_pdf(const CachePoint& a, const float* cdf, int R, const Vec3f& d) {
    const float z = dot(d, a.n);
    if (!(z > 0)) return 0.0f;
    float u, v;
    hemisphere_to_square(dot(d, a.t), dot(d, a.b), z, u, v);
    const int i = std::min(std::max(static_cast<int>(u * R), 0), R - 1);
    const int j = std::min(std::max(static_cast<int>(v * R), 0), R - 1);
    const int32_t t = j * R + i;
    const float p = cdf[t] - (t > 0 ? cdf[t - 1] : 0.0f);
    return p * static_cast<float>(R * R) / (2.0f * kPi);
}

// A world direction drawn from cache point a's guide: the texel by `pick`, the point in it
// by (u1, u2).
inline Vec3f pool_guide_sample(const CachePoint& a, const float* cdf, int R, float pick, float u1, float u2) {
    const int texel_count = R * R;
    int32_t t = static_cast<int32_t>(std::upper_bound(cdf, cdf + texel_count, pick) - cdf);
    t = std::min(t, texel_count - 1);
    while (t > 0 && !(cdf[t] > cdf[t - 1])) --t;  // never a texel of zero probability
    const float u = (static_cast<float>(t % R) + u1) / R, v = (static_cast<float>(t / R) + u2) / R;
    float x, y, z;
    square_to_hemisphere(u, v, x, y, z);
    return normalize(x * a.t + y * a.b + z * a.n);
}

}  // namespace cache
PATINA_END_TARGET
