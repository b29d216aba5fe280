// The camera: a pinhole or a thin lens, looking along `forward` with `up` the image's
// up, a vertical field of view, image x to the right and y down (row 0 at the top).
#pragma once

#include <cmath>

#include "core/constants.h"
#include "core/simd/target.h"
#include "core/vec3.h"

namespace patina {

struct Camera {
    float position[3] = {0, 0, 0};
    float forward[3] = {0, 0, -1};  // unit
    float right[3] = {1, 0, 0};     // unit, orthogonal to forward
    float up[3] = {0, 1, 0};        // unit, = cross(right, forward)
    float tan_half_fov = 0.5f;      // tan(vertical fov / 2)
    int width = 64, height = 64;
    float aperture_radius = 0;      // 0: pinhole
    float focus_distance = 1;       // along forward, for the thin lens
};

}  // namespace patina

// Inside the target namespace: each ISA's copy has its own symbols (see core/simd/target.h).
PATINA_BEGIN_TARGET

// The ray through film position (fx, fy) in pixels (x right, y down; (0, 0) the top-left
// corner of the image), with (lu, lv) in [0, 1)^2 choosing the point on the lens.
// `dir` is unit length.
inline void camera_ray(const Camera& c, float fx, float fy, float lu, float lv, Vec3f& org, Vec3f& dir) {
    const float aspect = static_cast<float>(c.width) / static_cast<float>(c.height);
    const float sx = (2.0f * fx / static_cast<float>(c.width) - 1.0f) * c.tan_half_fov * aspect;
    const float sy = (1.0f - 2.0f * fy / static_cast<float>(c.height)) * c.tan_half_fov;
    const Vec3f right = load_vec3(c.right), up = load_vec3(c.up);
    Vec3f o = load_vec3(c.position);
    Vec3f d = load_vec3(c.forward) + sx * right + sy * up;
    if (c.aperture_radius > 0) {
        // the point in focus along this pixel's pinhole ray, seen from a point on the lens disc
        const Vec3f focus = o + c.focus_distance * d;
        const float r = c.aperture_radius * std::sqrt(lu), phi = kTwoPi * lv;
        const float ox = r * std::cos(phi), oy = r * std::sin(phi);
        o = o + (ox * right + oy * up);
        d = focus - o;
    }
    const float inv = 1.0f / std::sqrt(dot(d, d));
    org = o;
    dir = inv * d;
}

PATINA_END_TARGET
