// Anisotropic GGX for the conductor and dielectric materials: the distribution,
// height-correlated Smith masking, and sampling of the normals visible from v (Heitz 2018,
// "Sampling the GGX distribution of visible normals"): the estimator's weight is then
// G2 / G1 <= 1 instead of growing without bound at grazing angles, which is what made
// rough glass fireflies. Local frame: z = normal, x = tangent (alpha_x along it). At
// alpha_x = alpha_y the distribution equals fit/microfacet.h's GGX.
#pragma once

#include "fit/microfacet.h"

PATINA_BEGIN_TARGET
namespace ggx_aniso {

template <class F>
PATINA_INLINE F d(const Vec3<F>& h, F ax, F ay) {
    const F x = h.x / ax, y = h.y / ay;
    const F t = x * x + y * y + h.z * h.z;
    return select(h.z > F(0.0f), F(1.0f) / (F(kPi) * ax * ay * t * t), F(0.0f));
}

template <class F>
PATINA_INLINE F lambda(const Vec3<F>& w, F ax, F ay) {
    const F x = w.x * ax, y = w.y * ay;
    const F tan2 = (x * x + y * y) / (w.z * w.z);
    return F(0.5f) * (sqrt_exact(F(1.0f) + tan2) - F(1.0f));
}

template <class F>
PATINA_INLINE F g2(const Vec3<F>& l, const Vec3<F>& v, F ax, F ay) {
    return F(1.0f) / (F(1.0f) + (lambda(l, ax, ay) + lambda(v, ax, ay)));
}

template <class F>
PATINA_INLINE F g1(const Vec3<F>& w, F ax, F ay) {
    return F(1.0f) / (F(1.0f) + lambda(w, ax, ay));
}

// A microfacet normal visible from v (v.z > 0), with density visible_pdf(v, h).
template <class F>
PATINA_INLINE Vec3<F> sample_visible(const Vec3<F>& v, F u1, F u2, F ax, F ay) {
    // v stretched to unit roughness, a frame around it
    F vx = ax * v.x, vy = ay * v.y, vz = v.z;
    const F inv_v = F(1.0f) / sqrt_exact(vx * vx + vy * vy + vz * vz);
    vx = vx * inv_v, vy = vy * inv_v, vz = vz * inv_v;
    const F len2 = vx * vx + vy * vy;
    const auto tilted = len2 > F(1e-14f);
    const F inv_len = F(1.0f) / sqrt_exact(max(len2, F(1e-14f)));
    const F t1x = select(tilted, -vy * inv_len, F(1.0f)), t1y = select(tilted, vx * inv_len, F(0.0f));
    // T2 = cross(V, T1), T1 = (t1x, t1y, 0)
    const F t2x = -vz * t1y, t2y = vz * t1x, t2z = vx * t1y - vy * t1x;
    // a point on the unit disc, its lower half squeezed by the projected visible hemisphere
    const F r = sqrt_exact(u1);
    F sn, cs;
    fast_sincos(F(2.0f * kPi) * u2, sn, cs);
    const F p1 = r * cs;
    const F s = F(0.5f) * (F(1.0f) + vz);
    const F p2 = madd(F(1.0f) - s, sqrt_exact(max(F(1.0f) - p1 * p1, F(0.0f))), s * (r * sn));
    const F p3 = sqrt_exact(max(F(1.0f) - p1 * p1 - p2 * p2, F(0.0f)));
    const F nx = p1 * t1x + p2 * t2x + p3 * vx;
    const F ny = p1 * t1y + p2 * t2y + p3 * vy;
    const F nz = p2 * t2z + p3 * vz;
    // back to the surface's roughness
    const F hx = ax * nx, hy = ay * ny, hz = max(nz, F(0.0f));
    const F inv_h = F(1.0f) / sqrt_exact(max(hx * hx + hy * hy + hz * hz, F(1e-30f)));
    return Vec3<F>{hx * inv_h, hy * inv_h, hz * inv_h};
}

// Density of sample_visible's h: G1(v) max(0, v.h) D(h) / v.z.
template <class F>
PATINA_INLINE F visible_pdf(const Vec3<F>& v, const Vec3<F>& h, F ax, F ay) {
    const F vh = v.x * h.x + v.y * h.y + v.z * h.z;
    return select((v.z > F(0.0f)) & (vh > F(0.0f)), g1(v, ax, ay) * vh * d(h, ax, ay) / v.z, F(0.0f));
}

// pdf of l = reflect(v about h), h from sample_visible: visible_pdf / (4 v.h) = G1(v) D(h) / (4 v.z).
template <class F>
PATINA_INLINE F pdf(const Vec3<F>& v, const Vec3<F>& l, F ax, F ay) {
    const Vec3<F> h = microfacet::half_vector(v, l);
    const F vh = v.x * h.x + v.y * h.y + v.z * h.z;
    return select((l.z > F(0.0f)) & (vh > F(0.0f)), visible_pdf(v, h, ax, ay) / (F(4.0f) * vh), F(0.0f));
}

// l reflected about a GGX normal visible from v (density pdf).
template <class F>
PATINA_INLINE Vec3<F> sample_reflection(const Vec3<F>& v, F u1, F u2, F ax, F ay) {
    return microfacet::reflect(v, sample_visible(v, u1, u2, ax, ay));
}

}  // namespace ggx_aniso
PATINA_END_TARGET
