// The adaptive sampler's corner signals channel by channel (a structure of arrays), so that
// round 1's comparisons of neighbouring corners run over a row of the tile at a time: the
// compiler turns the loop into SIMD lanes (four to eight pairs a step) where the scalar
// aa_differs (render/antialiasing/adaptive_sampler.h) took one pair and its branches on the
// data. Each lane computes exactly aa_differs's operations in the same order (the build
// keeps floating-point contraction off), so the decisions are the same bit for bit;
// tests/cpp/render/antialiasing/test_signal_lanes.cpp checks it lane by lane.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/integrators/integrator.h"

namespace patina {

struct AaSignalLanes {
    std::vector<float> colour[3], normal[3], depth;

    void resize(size_t n) {
        for (int k = 0; k < 3; ++k) {
            colour[k].resize(n);
            normal[k].resize(n);
        }
        depth.resize(n);
    }
    // position q's signal from its trace (the radiance, shading normal and depth)
    void set(size_t q, const PathResult& r) {
        for (int k = 0; k < 3; ++k) {
            colour[k][q] = r.rgb[k];
            normal[k][q] = r.normal[k];
        }
        depth[q] = r.depth;
    }
};

// out[k] = aa_differs(signal a + k, signal b + k, threshold) for k < n: the positions a + k
// and b + k of `lanes` compared pairwise. Every test is evaluated in every lane and the
// outcomes combined with bit operations, no branch, so the loop vectorises.
// (`out` restrict: the compiler need not check fifteen arrays for overlap)
inline void aa_differs_lanes(const AaSignalLanes& lanes, size_t a, size_t b, size_t n, float threshold,
                             uint8_t* __restrict out) {
    const int broken = 1.0f > threshold;     // what a contrast of 1 decides
    const int flat_bent = 0.0f > threshold;  // and one of 0
    const auto finite = [](float x) { return static_cast<int>(std::fabs(x) <= 3.40282347e38f); };  // 0 for inf, NaN
    // |x - y| / (|x| + |y|) > threshold multiplied out; a broken value decides `broken`
    const auto step = [&](float x, float y) {
        const int both = finite(x) & finite(y);
        const int differs = std::fabs(x - y) > threshold * (std::fabs(x) + std::fabs(y));
        return (both & differs) | ((both ^ 1) & broken);
    };
    const float *r = lanes.colour[0].data(), *g = lanes.colour[1].data(), *bl = lanes.colour[2].data();
    const float *nx = lanes.normal[0].data(), *ny = lanes.normal[1].data(), *nz = lanes.normal[2].data();
    const float* depth = lanes.depth.data();
    for (size_t k = 0; k < n; ++k) {
        const size_t p = a + k, q = b + k;
        const int ha = finite(depth[p]), hb = finite(depth[q]);
        const int colour = step(r[p], r[q]) | step(g[p], g[q]) | step(bl[p], bl[q]);
        const float d = nx[p] * nx[q] + ny[p] * ny[q] + nz[p] * nz[q];
        // 0.5 (1 - clamp(d, -1, 1)) > threshold, the clamp's three cases as masks (a float
        // select stopped the compiler's vectorising): below -1 it is 1 > threshold, above 1 0 > threshold
        const int below = d < -1.0f, above = d > 1.0f;
        const int bent = (below & broken) | (above & flat_bent) |
                         (((below | above) ^ 1) & (0.5f * (1.0f - d) > threshold));
        const int normal = (finite(d) & bent) | ((finite(d) ^ 1) & broken);
        const int surface = step(depth[p], depth[q]) | normal;  // both hit (a miss's depth is inf)
        const int split = ha ^ hb;
        out[k] = static_cast<uint8_t>((split & broken) | ((split ^ 1) & (colour | (ha & surface))));
    }
}

}  // namespace patina
