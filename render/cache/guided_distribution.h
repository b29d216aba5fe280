// cache-guided's sampling distribution over a cache point's texels (docs/radiance-cache.md,
// "cache-guided"): the cached incident radiance times the cosine, made robust against the
// cache's noise. Each texel of a cache point is one path sample, so a texel whose sample
// found no light may lie where the light is; a guide that trusts single texels gives such
// directions almost no probability, and the one-sample MIS weight of a path that does find
// light there is then up to 1 / (1 - cache.guide) times the BRDF's: fireflies (measured:
// single pixels 16 to 500 times path's variance). So the radiance is averaged over cells of
// kGuideCell x kGuideCell texels before the product, and every texel keeps a floor of
// kGuideFloor times the mean value.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/constants.h"
#include "core/simd/target.h"

PATINA_BEGIN_TARGET
namespace cache {

constexpr int kGuideCell = 3;
constexpr float kGuideFloor = 0.3f;

// The cumulative distribution (cdf[0 .. R^2), ending at 1) over the texels of an R x R
// hemisphere of `radiance` (RGB per texel) times cos_z (the texel centres' cosines, one per
// texel); `cell` scratch of R^2 x 3 floats. Returns false (cdf unusable) when the product
// is zero or not finite everywhere.
inline bool guide_cdf(const float* radiance, const float* cos_z, int R, float* cell, float* cdf) {
    const int c = std::min(kGuideCell, R);
    const size_t texel_count = static_cast<size_t>(R) * R;
    // the radiance averaged over its cell (cells at the edge: what is left of them)
    for (int j0 = 0; j0 < R; j0 += c)
        for (int i0 = 0; i0 < R; i0 += c) {
            const int j1 = std::min(R, j0 + c), i1 = std::min(R, i0 + c);
            double sum[3] = {0, 0, 0};
            for (int j = j0; j < j1; ++j)
                for (int i = i0; i < i1; ++i)
                    for (int k = 0; k < 3; ++k) sum[k] += radiance[3 * (j * R + i) + k];
            const double inv = 1.0 / ((j1 - j0) * (i1 - i0));
            for (int j = j0; j < j1; ++j)
                for (int i = i0; i < i1; ++i)
                    for (int k = 0; k < 3; ++k) cell[3 * (j * R + i) + k] = static_cast<float>(sum[k] * inv);
        }
    double acc = 0;
    for (size_t t = 0; t < texel_count; ++t) {
        acc += std::max(0.0f, luminance(cell + 3 * t)) * cos_z[t];
        cdf[t] = static_cast<float>(acc);
    }
    if (!(acc > 0) || !std::isfinite(acc)) return false;
    const double floor_value = kGuideFloor * acc / static_cast<double>(texel_count);
    const double total = acc + floor_value * static_cast<double>(texel_count);
    const double inv = 1.0 / total;
    for (size_t t = 0; t < texel_count; ++t)
        cdf[t] = static_cast<float>((cdf[t] + floor_value * static_cast<double>(t + 1)) * inv);
    cdf[texel_count - 1] = 1.0f;
    return true;
}

}  // namespace cache
PATINA_END_TARGET
