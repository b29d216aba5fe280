// Importance sampling of an RGL material by its own warps, N lanes at a time (Dupuy & Jakob
// 2018, section 5; Mitsuba 3's `measured`): a uniform point is warped by the luminance warp
// (where the reflected energy is) and then by the VNDF warp (to a microfacet normal m), both
// given the incident angles; wo is wi reflected about m. Its pdf is what rgl_pdf_block gives
// for the same pair, up to float rounding:
//   luminance density x VNDF density / (d omega_m / d u_m = 2 pi^2 u sin theta_m) / (4 <wi, m>).
#pragma once

#include "brdf/rgl/rgl_eval.h"
#include "brdf/rgl/rgl_warp_sample.h"

PATINA_BEGIN_TARGET

template <int N>
struct RglSampled {
    Vec3<vfloat<N>> wo;  // the normal where pdf is 0
    vfloat<N> pdf;       // per steradian; 0 when wi or the sampled wo is below the horizon
};

// u1, u2 uniform in [0, 1); wi unit directions in the surface's frame (z = normal).
template <int N>
PATINA_INLINE RglSampled<N> rgl_sample_block(const RglView& v, Vec3<vfloat<N>> wi, vfloat<N> u1, vfloat<N> u2,
                                             RglHints& hints) {
    using F = vfloat<N>;
    using namespace rgl_detail;
    const F zero(0.0f), one(1.0f);
    const vbool<N> above = wi.z > zero;
    wi = Vec3<F>{select(above, wi.x, zero), select(above, wi.y, zero), select(above, wi.z, one)};
    Vec3<F> folded = wi, unused = wi;
    fold<N>(v, folded, unused);
    const F theta_i = elevation<N>(folded), phi_i = fast_atan2(folded.y, folded.x);
    const RglParams<N> params = rgl_params<N>(v, phi_i, theta_i, above, hints);
    const F lo(1e-7f), hi(1.0f - 1e-7f);
    const RglWarpPoint<N> s = rgl_warp_sample<N>(v.luminance, params, clamp(u1, lo, hi), clamp(u2, lo, hi));
    const RglWarpPoint<N> u_m = rgl_warp_sample<N>(v.vndf, params, s.x, s.y);
    const F theta_m = u_m.x * u_m.x * F(kHalfPi);
    F phi_m = (F(2.0f) * u_m.y - one) * F(kPi);
    if (v.isotropic) phi_m = phi_m + phi_i;
    F sin_t, cos_t, sin_p, cos_p;
    fast_sincos(theta_m, sin_t, cos_t);
    fast_sincos(phi_m, sin_p, cos_p);
    const Vec3<F> m{sin_t * cos_p, sin_t * sin_p, cos_t};
    const F cos_im = folded.x * m.x + folded.y * m.y + folded.z * m.z;
    const F twice = F(2.0f) * cos_im;
    Vec3<F> wo{twice * m.x - folded.x, twice * m.y - folded.y, twice * m.z - folded.z};
    fold<N>(v, wi, wo);  // back from the file's azimuthal range: the mirror is its own inverse
    const vbool<N> valid = above & (wo.z > zero) & (cos_im > zero);
    const F jacobian = max(F(static_cast<float>(2.0 * kPiDouble * kPiDouble)) * u_m.x * sin_t, F(1e-6f)) * F(4.0f) * cos_im;
    RglSampled<N> r;
    r.pdf = select(valid, s.density * u_m.density / jacobian, zero);
    r.wo = Vec3<F>{select(valid, wo.x, zero), select(valid, wo.y, zero), select(valid, wo.z, one)};
    return r;
}

PATINA_END_TARGET
