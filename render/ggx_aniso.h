// Anisotropic GGX for the conductor material: the distribution, height-correlated Smith
// masking and sampling of D(h) cos(theta_h) by stretching unit-roughness slopes
// (Heitz 2014, "Understanding the masking-shadowing function"). Local frame: z = normal,
// x = tangent (alpha_x along it). At alpha_x = alpha_y it equals fit/microfacet.h's GGX.
#pragma once

#include "fit/microfacet.h"

PATINA_BEGIN_TARGET
namespace ggx_aniso {

template <class F>
PATINA_INLINE F d(const Dir3<F>& h, F ax, F ay) {
    const F x = h.x / ax, y = h.y / ay;
    const F t = x * x + y * y + h.z * h.z;
    return select(h.z > F(0.0f), F(1.0f) / (F(microfacet::kPi) * ax * ay * t * t), F(0.0f));
}

template <class F>
PATINA_INLINE F lambda(const Dir3<F>& w, F ax, F ay) {
    const F x = w.x * ax, y = w.y * ay;
    const F tan2 = (x * x + y * y) / (w.z * w.z);
    return F(0.5f) * (sqrt_exact(F(1.0f) + tan2) - F(1.0f));
}

template <class F>
PATINA_INLINE F g2(const Dir3<F>& l, const Dir3<F>& v, F ax, F ay) {
    return F(1.0f) / (F(1.0f) + (lambda(l, ax, ay) + lambda(v, ax, ay)));
}

// A microfacet normal with density D(h) cos(theta_h).
template <class F>
PATINA_INLINE Dir3<F> sample_h(F u1, F u2, F ax, F ay) {
    const F r = sqrt_exact(u1 / max(F(1.0f) - u1, F(1e-7f)));
    F s, c;
    fast_sincos(F(2.0f * microfacet::kPi) * u2, s, c);
    const F x = r * c * ax, y = r * s * ay;
    const F inv = F(1.0f) / sqrt_exact(x * x + y * y + F(1.0f));
    return Dir3<F>{x * inv, y * inv, inv};
}

// pdf of l = reflect(v about h) with h from sample_h: D(h) cos(theta_h) / (4 |v . h|).
template <class F>
PATINA_INLINE F pdf(const Dir3<F>& v, const Dir3<F>& l, F ax, F ay) {
    const Dir3<F> h = microfacet::half_vector(v, l);
    return microfacet::reflected_pdf(v, l, d(h, ax, ay), h);
}

}  // namespace ggx_aniso
PATINA_END_TARGET
