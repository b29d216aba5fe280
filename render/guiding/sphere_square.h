// The unit sphere of directions as the unit square, by the equal-area cylindrical map
// (Lambert's): u = azimuth / 2 pi about world z, v = (cos theta + 1) / 2. Equal areas on the
// square are equal solid angles (d omega = 4 pi du dv), so a density on the square divided
// by 4 pi is a density in solid angle, and the directional quadtree (directional_tree.h)
// partitions the sphere into cells of known solid angle. World space, not a shading frame:
// one distribution serves every vertex of a spatial cell, whatever its normal.
//
// u itself needs an arc tangent (no algebraic form exists for an angle), but a lookup only
// needs which side of a cell's boundary u lies on, and that is algebraic: u >= k / 2^L is the
// sign of the cross product of the direction's (x, y) with the boundary's (cos, sin), which
// AzimuthBoundaries tabulates (DirectionalTree::density_at_direction). The boundaries are
// the same cos / sin square_to_direction evaluates, so the lookup agrees with sampling up to
// rounding.
// Plain inline code for the guide's .cpp files (compiled once, not per SIMD width).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "core/constants.h"

namespace patina::guiding {

inline constexpr float kSphereArea = 4.0f * kPi;

inline void direction_to_square(const float* d, float& u, float& v) {
    float phi = std::atan2(d[1], d[0]) * (1.0f / kTwoPi);
    if (phi < 0.0f) phi += 1.0f;
    u = std::min(std::max(phi, 0.0f), 0x1.fffffep-1f);
    v = std::min(std::max(0.5f * (d[2] + 1.0f), 0.0f), 0x1.fffffep-1f);
}

inline void square_to_direction(float u, float v, float* d) {
    const float z = std::min(std::max(2.0f * v - 1.0f, -1.0f), 1.0f);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = kTwoPi * u;
    d[0] = r * std::cos(phi);
    d[1] = r * std::sin(phi);
    d[2] = z;
}

// The unit vectors (cos, sin)(2 pi (2c + 1) / 2^L): the azimuth boundary a cell of column c
// at level L - 1 splits at, for L = 1 .. kLevels, level by level as a heap (index 2^(L-1) + c)
// so that the upper levels every lookup tests share a few cache lines.
struct AzimuthBoundaries {
    static constexpr int kLevels = 12;
    float cos_sin[2 << kLevels];
    AzimuthBoundaries() {
        cos_sin[0] = cos_sin[1] = 0.0f;  // index 0: unused
        for (int level = 1; level <= kLevels; ++level)
            for (int c = 0; c < 1 << (level - 1); ++c) {
                const float phi = kTwoPi * (static_cast<float>(2 * c + 1) / static_cast<float>(1 << level));
                const size_t i = (size_t{1} << (level - 1)) + static_cast<size_t>(c);
                cos_sin[2 * i] = std::cos(phi);
                cos_sin[2 * i + 1] = std::sin(phi);
            }
    }
    static const AzimuthBoundaries& get() {
        static const AzimuthBoundaries table;
        return table;
    }
};

// Whether direction d's u is at or above the boundary (2 cell + 1) / 2^level, the middle of
// column `cell` of level - 1, given that u lies within a quarter turn of it (every level
// below the root: cells half a turn wide or less).
inline bool azimuth_at_or_above(const float* d, const AzimuthBoundaries& b, uint32_t cell, int level) {
    const float* cs = b.cos_sin + 2 * ((size_t{1} << (level - 1)) + cell);
    return cs[0] * d[1] - cs[1] * d[0] >= 0.0f;
}

}  // namespace patina::guiding
