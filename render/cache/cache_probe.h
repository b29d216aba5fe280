// The radiance cache at one point, for the pictures of docs/radiance-cache.md
// (tools/draw_radiance_cache.py) and the tests: a cache point built at A, reprojected into B,
// B's holes traced, and B's own hemisphere traced in full for comparison. Texel j * R + i
// of each R x R array; RGB arrays R^2 x 3.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace patina {

struct CacheProbe {
    int resolution = 0;
    // A: its texture, what each texel saw (0 hit, 1 miss, 2 under the surface), the hit
    // distance, and the depth layer and surfel of each hit (-1: none)
    std::vector<float> a_radiance, a_dist;
    std::vector<uint8_t> a_kind;
    std::vector<int32_t> a_layer, a_surfel;
    size_t surfels = 0, silhouettes = 0;
    // B: its masks after the reprojection (1 where set), the radiance reprojected (-1 in
    // the texels left to trace), after tracing those, and B's own hemisphere traced in full
    std::vector<uint8_t> filled, unknown, to_trace;
    std::vector<float> b_reprojected, b_radiance, b_reference;
};

}  // namespace patina
