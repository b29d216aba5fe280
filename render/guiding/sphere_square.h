// The unit sphere of directions as the unit square, by the equal-area cylindrical map
// (Lambert's): u = azimuth / 2 pi about world z, v = (cos theta + 1) / 2. Equal areas on the
// square are equal solid angles (d omega = 4 pi du dv), so a density on the square divided
// by 4 pi is a density in solid angle, and the directional quadtree (directional_tree.h)
// partitions the sphere into cells of known solid angle. World space, not a shading frame:
// one distribution serves every vertex of a spatial cell, whatever its normal.
// Plain inline code for the guide's .cpp files (compiled once, not per SIMD width).
#pragma once

#include <algorithm>
#include <cmath>

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

}  // namespace patina::guiding
