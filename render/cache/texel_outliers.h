// A bound on a hemisphere's isolated bright texels (docs/radiance-cache.md, "Fireflies in a
// cache point's texels"). A texel is one path sample of the incident indirect radiance: a
// rare path that finds the sun through a gap, or the sun in a glossy lobe, makes one texel
// hundreds to thousands of times its neighbours, and every point that reuses the hemisphere
// takes that one sample's noise: a blotch (cache-car at seed 0: 58 pixels of the rear wheel
// at 25 times the converged radiance). Light legitimately concentrated (a sunlit patch, a
// bright wall seen at grazing angles) spans neighbouring texels: a texel is bounded by
// kOutlierBound times the brightest of its eight neighbours (or the mean of the other
// texels, if brighter: the texel's own light would raise its own bound), so only a texel far
// above everything around it loses light. Applied to each cache point's texture when it is
// built and to each reconstructed hemisphere after its holes are traced
// (radiance_cache_impl.h). Plain scalar code in texel order: the same bits at every SIMD width.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "core/constants.h"
#include "core/simd/target.h"

PATINA_BEGIN_TARGET
namespace cache {

// The bias it adds is the rare paths' light it removes, which in the room (the sun reflected by
// its glossy floor, caught by single texels) is real light: the bench's bias on the room at
// 128, 256 and 512 read -1.9, -1.3 and -1.1 % (-1.0 unbounded, the bound 2 %), the car's
// seed 0 relMSE 0.0022, 0.0027 and 0.0044 (0.054 unbounded; seeds 1-3 about 0.0018).
constexpr float kOutlierBound = 128.0f;

// The luminance of each of R x R texels (RGB) into `luminances`; returns their sum.
inline double texel_luminances(const float* radiance, int R, std::vector<float>& luminances) {
    const size_t texel_count = static_cast<size_t>(R) * R;
    luminances.resize(texel_count);
    double sum = 0;
    for (size_t t = 0; t < texel_count; ++t) {
        luminances[t] = std::max(luminance(radiance + 3 * t), 0.0f);
        sum += luminances[t];
    }
    return sum;
}

// The brightest of texel (x, y)'s eight neighbours inside the R x R square, at least `floor`.
inline float brightest_neighbour(const std::vector<float>& luminances, int R, int x, int y, float floor) {
    float brightest = floor;
    for (int ny = std::max(y - 1, 0); ny <= std::min(y + 1, R - 1); ++ny)
        for (int nx = std::max(x - 1, 0); nx <= std::min(x + 1, R - 1); ++nx)
            if (nx != x || ny != y) brightest = std::max(brightest, luminances[static_cast<size_t>(ny) * R + nx]);
    return brightest;
}

// Scales down (keeping its colour) every texel of the R x R texture `radiance` (RGB) brighter
// than kOutlierBound times its brightest neighbour and the mean of the other texels; the
// bounds are taken from the texture as it was. Returns how many texels it bounded.
inline int bound_isolated_texels(float* radiance, int R, std::vector<float>& luminances) {
    const double sum = texel_luminances(radiance, R, luminances);
    const double other_texels = static_cast<double>(R) * R - 1;
    int bounded = 0;
    for (int y = 0; y < R; ++y)
        for (int x = 0; x < R; ++x) {
            const size_t t = static_cast<size_t>(y) * R + x;
            const float Y = luminances[t];
            const float others_mean = static_cast<float>(std::max(sum - Y, 0.0) / other_texels);
            if (!(Y > kOutlierBound * others_mean)) continue;  // most texels: no neighbour can bound it lower
            const float bound = kOutlierBound * brightest_neighbour(luminances, R, x, y, others_mean);
            if (!(Y > bound)) continue;
            const float scale = bound / Y;
            for (int c = 0; c < 3; ++c) radiance[3 * t + c] *= scale;
            ++bounded;
        }
    return bounded;
}

}  // namespace cache
PATINA_END_TARGET
