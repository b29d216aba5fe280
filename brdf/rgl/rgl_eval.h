// An RGL material evaluated by the format's own rule, N direction pairs at a time
// (rgl_brdf.RglBrdf.eval is the double-precision reference):
//   m = normalize(wi + wo); u = (sqrt(2 theta / pi), (phi + pi) / 2 pi) of wi and of m
//   (phi_m relative to phi_i for an isotropic file); s = the inverse VNDF warp of u_m given
//   (phi_i, theta_i); f = values(s | phi_i, theta_i) [* ndf(u_m) / (4 sigma(u_wi))] / cos theta_o.
// Lanes never mix: every width gives width 1's bits (the fast inverse trigonometry and the
// searches are lane-exact), and coherent pairs share their incident-angle cells, so the
// searches walk one path and the blends read neighbouring grids.
#pragma once

#include "brdf/rgl/rgl_grid.h"
#include "brdf/rgl/rgl_params.h"
#include "brdf/rgl/rgl_view.h"
#include "core/constants.h"
#include "core/simd/fastmath.h"
#include "core/vec3.h"

PATINA_BEGIN_TARGET

namespace rgl_detail {
// acos(z) of a unit vector without acos's loss of precision near the pole (where the square
// root mapping is steepest): 2 asin(|d - n| / 2).
template <int N>
PATINA_INLINE vfloat<N> elevation(const Vec3<vfloat<N>>& d) {
    using F = vfloat<N>;
    const F dz = d.z - F(1.0f);
    const F dist = sqrt_exact(d.x * d.x + d.y * d.y + dz * dz);
    return F(2.0f) * fast_asin(min(F(0.5f) * dist, F(1.0f)));
}

template <int N>
PATINA_INLINE vfloat<N> theta_to_u(vfloat<N> theta) {
    using F = vfloat<N>;
    return sqrt_exact(max(theta, F(0.0f)) * F(static_cast<float>(2.0 / kPiDouble)));
}

template <int N>
PATINA_INLINE vfloat<N> phi_to_u(vfloat<N> phi) {
    using F = vfloat<N>;
    return (phi + F(kPi)) * F(static_cast<float>(0.5 / kPiDouble));
}

// Files of reduced azimuthal range hold phi_i over 180 or 90 degrees: pairs are mirrored into
// it (x and y flipped by the signs of wi), as Mitsuba's `measured` does.
template <int N>
PATINA_INLINE void fold(const RglView& v, Vec3<vfloat<N>>& wi, Vec3<vfloat<N>>& wo) {
    using F = vfloat<N>;
    if (v.reduction < 2) return;
    const F flip_y = select(wi.y >= F(0.0f), F(-1.0f), F(1.0f));
    const F flip_x = v.reduction == 4 ? select(wi.x >= F(0.0f), F(-1.0f), F(1.0f)) : flip_y;
    wi.x = wi.x * flip_x;
    wi.y = wi.y * flip_y;
    wo.x = wo.x * flip_x;
    wo.y = wo.y * flip_y;
}
}  // namespace rgl_detail

// Everything about one block of pairs the evaluation and the pdf share.
template <int N>
struct RglPairs {
    vbool<N> above;  // both directions above the horizon (the others were replaced by the normal)
    Vec3<vfloat<N>> wi, wo, half;
    vfloat<N> u_wi_x, u_wi_y, u_m_x, u_m_y;
    RglParams<N> params;
};

template <int N>
PATINA_INLINE RglPairs<N> rgl_pairs(const RglView& v, Vec3<vfloat<N>> wi, Vec3<vfloat<N>> wo, RglHints& hints) {
    using F = vfloat<N>;
    using namespace rgl_detail;
    RglPairs<N> q;
    q.above = (wi.z > F(0.0f)) & (wo.z > F(0.0f));
    // pairs below the horizon (and padding) become the normal pair: every index stays in range
    const F zero(0.0f), one(1.0f);
    wi = Vec3<F>{select(q.above, wi.x, zero), select(q.above, wi.y, zero), select(q.above, wi.z, one)};
    wo = Vec3<F>{select(q.above, wo.x, zero), select(q.above, wo.y, zero), select(q.above, wo.z, one)};
    fold<N>(v, wi, wo);
    F hx = wi.x + wo.x, hy = wi.y + wo.y, hz = wi.z + wo.z;
    const F inv_len = one / sqrt_exact(hx * hx + hy * hy + hz * hz);
    q.half = Vec3<F>{hx * inv_len, hy * inv_len, hz * inv_len};
    q.wi = wi;
    q.wo = wo;
    const F theta_i = elevation<N>(wi), phi_i = fast_atan2(wi.y, wi.x);
    const F theta_m = elevation<N>(q.half), phi_m = fast_atan2(q.half.y, q.half.x);
    q.u_wi_x = theta_to_u<N>(theta_i);
    q.u_wi_y = phi_to_u<N>(phi_i);
    q.u_m_x = theta_to_u<N>(theta_m);
    const F u_m_y = phi_to_u<N>(v.isotropic ? phi_m - phi_i : phi_m);
    q.u_m_y = u_m_y - floor(u_m_y);
    q.params = rgl_params<N>(v, phi_i, theta_i, q.above, hints);
    return q;
}

// f(wi, wo) per channel (linear sRGB, 1/sr); 0 below the horizon.
template <int N>
PATINA_INLINE void rgl_eval_block(const RglView& v, const Vec3<vfloat<N>>& wi, const Vec3<vfloat<N>>& wo,
                                  RglHints& hints, vfloat<N> (&rgb)[kRglChannels]) {
    using F = vfloat<N>;
    const RglPairs<N> q = rgl_pairs<N>(v, wi, wo, hints);
    const RglWarpPoint<N> s = rgl_warp_invert<N>(v.vndf, q.params, q.u_m_x, q.u_m_y);
    const RglPatch<N> patch = rgl_patch<N>(s.x, s.y, v.values.height, v.values.width);
    F scale = F(1.0f) / q.wo.z;  // the file holds f cos(theta_o)
    if (v.jacobian) {
        const F ndf = rgl_grid_eval<N>(v.ndf, q.u_m_x, q.u_m_y);
        const F sigma = rgl_grid_eval<N>(v.sigma, q.u_wi_x, q.u_wi_y);
        scale = ndf / (F(4.0f) * sigma) * scale;
    }
    for (int c = 0; c < kRglChannels; ++c) {
        const F value = rgl_values_eval<N>(v.values, q.params, patch, c);
        rgb[c] = select(q.above, max(value, F(0.0f)) * scale, F(0.0f));
    }
}

// The density of wo that sampling by the file's warps (luminance, then vndf) gives, per
// steradian; 0 below the horizon.
template <int N>
PATINA_INLINE vfloat<N> rgl_pdf_block(const RglView& v, const Vec3<vfloat<N>>& wi, const Vec3<vfloat<N>>& wo,
                                      RglHints& hints) {
    using F = vfloat<N>;
    const RglPairs<N> q = rgl_pairs<N>(v, wi, wo, hints);
    const RglWarpPoint<N> s = rgl_warp_invert<N>(v.vndf, q.params, q.u_m_x, q.u_m_y);
    const F luminance = rgl_warp_density<N>(v.luminance, q.params, s.x, s.y);
    // d(omega_m) / d(u_m) = 2 pi^2 u sin(theta_m), and d(omega_o) / d(omega_m) = 4 <wi, m>
    const F sin_m = sqrt_exact(q.half.x * q.half.x + q.half.y * q.half.y);
    const F jacobian = max(F(static_cast<float>(2.0 * kPiDouble * kPiDouble)) * q.u_m_x * sin_m, F(1e-6f)) * F(4.0f) *
                       (q.wi.x * q.half.x + q.wi.y * q.half.y + q.wi.z * q.half.z);
    return select(q.above, s.density * luminance / jacobian, F(0.0f));
}

PATINA_END_TARGET
