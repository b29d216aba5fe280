// The radiance cache's hemisphere parametrization (docs/radiance-cache.md): the unit square
// [0, 1]^2 onto the hemisphere z >= 0 of a local frame, equal-area, so every texel of an
// R x R grid subtends the same solid angle 2 pi / R^2 and integrating over the hemisphere is
// a plain sum over texels. The square goes to the unit disk by Shirley and Chiu's concentric
// map (squares to circles, low distortion, continuous inside), the disk to the hemisphere by
// Lambert's azimuthal equal-area lift: r^2 = 1 - z. The inverse is defined on the whole
// sphere but the south pole: directions below the horizon (z < 0, r up to sqrt 2) land
// outside the square, continuously, so a surfel crossing a point's horizon still projects
// to one convex-ish region that the rasterizer clips.
//
// One template for float and vfloat<N>: the polynomials of core/simd/fastmath.h give the
// same bits at every width.
#pragma once

#include "core/constants.h"
#include "core/simd/fastmath.h"
#include "core/simd/simd.h"

PATINA_BEGIN_TARGET
namespace cache {

constexpr float kQuarterPi = 0.78539816339744831f;

// The local direction (x, y, z) of square point (u, v).
template <class F>
PATINA_INLINE void square_to_hemisphere(F u, F v, F& x, F& y, F& z) {
    const F a = F(2.0f) * u - F(1.0f), b = F(2.0f) * v - F(1.0f);
    const auto first = abs(a) > abs(b);
    const auto zero = (a == F(0.0f)) & (b == F(0.0f));
    // the disk radius r and angle phi (Shirley-Chiu): r = a, phi = pi/4 b/a where |a| > |b|
    const F r = select(first, a, b);
    const F ratio = select(zero, F(0.0f), select(first, b / a, a / b));
    const F phi = select(first, F(kQuarterPi) * ratio, F(2.0f * kQuarterPi) - F(kQuarterPi) * ratio);
    F s, c;
    fast_sincos(phi, s, c);
    const F r2 = r * r;
    const F lift = sqrt_exact(max(F(2.0f) - r2, F(0.0f)));  // Lambert: |xy| = r sqrt(2 - r^2)
    x = r * c * lift;
    y = r * s * lift;
    z = F(1.0f) - r2;
}

// The square point (u, v) of a unit direction; z < 0 lands outside [0, 1]^2 (|2u - 1| or
// |2v - 1| up to sqrt 2).
template <class F>
PATINA_INLINE void hemisphere_to_square(F x, F y, F z, F& u, F& v) {
    const F r = sqrt_exact(max(F(1.0f) - z, F(0.0f)));
    const F ax = abs(x), ay = abs(y);
    const F hi = max(ax, ay), lo = min(ax, ay);
    // the angle from the nearer axis, in [0, pi/4], scaled to the square's [0, 1]
    const F t = select(hi > F(0.0f), fast_atan(lo / hi) * F(1.0f / kQuarterPi), F(0.0f));
    const auto x_major = ax >= ay;
    const F a = select(x_major, r, r * t), b = select(x_major, r * t, r);
    u = F(0.5f) * (copysign(a, x) + F(1.0f));
    v = F(0.5f) * (copysign(b, y) + F(1.0f));
}

// The solid angle of one texel of an R x R grid.
PATINA_INLINE float texel_solid_angle(int resolution) {
    return 2.0f * kPi / static_cast<float>(resolution * resolution);
}

}  // namespace cache
PATINA_END_TARGET
