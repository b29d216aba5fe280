// Bilinear lookups in an RGL material's 2-D grids, N lanes at a time: a plain grid (ndf,
// sigma), a grid blended over the incident angles (the values), and the inverse of a warp
// (vndf: the point of the unit square the warp maps onto a given one, and the density there),
// as rgl_warp.Interpolant2D.eval / .invert do in double precision.
#pragma once

#include "brdf/rgl/rgl_params.h"
#include "brdf/rgl/rgl_view.h"
#include "core/simd/simd.h"

PATINA_BEGIN_TARGET

// A point's patch in a (height x width) grid over [0, 1]^2: its first node and row, and its
// place within the patch (fractions in [0, 1] inside the square).
template <int N>
struct RglPatch {
    vint<N> node, row;
    vfloat<N> fx, fy;
};

template <int N>
PATINA_INLINE RglPatch<N> rgl_patch(vfloat<N> x, vfloat<N> y, int height, int width) {
    using F = vfloat<N>;
    const F gx = x * F(static_cast<float>(width - 1)), gy = y * F(static_cast<float>(height - 1));
    const F cx = clamp(floor(gx), F(0.0f), F(static_cast<float>(width - 2)));
    const F cy = clamp(floor(gy), F(0.0f), F(static_cast<float>(height - 2)));
    RglPatch<N> p;
    p.row = to_int_trunc(cy);
    p.node = to_int_trunc(cx) + p.row * vint<N>(width);
    p.fx = gx - cx;
    p.fy = gy - cy;
    return p;
}

template <int N>
PATINA_INLINE vfloat<N> rgl_bilinear(vfloat<N> fx, vfloat<N> fy, vfloat<N> v00, vfloat<N> v10, vfloat<N> v01,
                                     vfloat<N> v11) {
    using F = vfloat<N>;
    const F one(1.0f);
    return (one - fy) * ((one - fx) * v00 + fx * v10) + fy * ((one - fx) * v01 + fx * v11);
}

// A grid without parameters (ndf, sigma) at (x, y).
template <int N>
PATINA_INLINE vfloat<N> rgl_grid_eval(const RglGridView& g, vfloat<N> x, vfloat<N> y) {
    using I = vint<N>;
    const RglPatch<N> p = rgl_patch<N>(x, y, g.height, g.width);
    return rgl_bilinear<N>(p.fx, p.fy, gather(g.data, p.node), gather(g.data, p.node + I(1)),
                           gather(g.data, p.node + I(g.width)), gather(g.data, p.node + I(g.width + 1)));
}

// Grid `slice_offset` of the values (channel c: slices are (phi_i, theta_i, channel)) at the
// patch, blended over the incident angles.
template <int N>
PATINA_INLINE vfloat<N> rgl_values_eval(const RglGridView& g, const RglParams<N>& params, const RglPatch<N>& p,
                                        int channel) {
    using I = vint<N>;
    const int cells = g.height * g.width;
    const float* table = g.data + channel * cells;
    const int stride = kRglChannels * cells;
    return rgl_bilinear<N>(p.fx, p.fy, rgl_blend<N>(table, stride, params, p.node),
                           rgl_blend<N>(table, stride, params, p.node + I(1)),
                           rgl_blend<N>(table, stride, params, p.node + I(g.width)),
                           rgl_blend<N>(table, stride, params, p.node + I(g.width + 1)));
}

// The warp's density at (x, y) (luminance: the pdf of the sample point), per unit area.
template <int N>
PATINA_INLINE vfloat<N> rgl_warp_density(const RglWarpView& w, const RglParams<N>& params, vfloat<N> x,
                                         vfloat<N> y) {
    using I = vint<N>;
    const RglPatch<N> p = rgl_patch<N>(x, y, w.height, w.width);
    const int cells = w.height * w.width;
    const vfloat<N> value = rgl_bilinear<N>(
        p.fx, p.fy, rgl_blend<N>(w.data, cells, params, p.node), rgl_blend<N>(w.data, cells, params, p.node + I(1)),
        rgl_blend<N>(w.data, cells, params, p.node + I(w.width)),
        rgl_blend<N>(w.data, cells, params, p.node + I(w.width + 1)));
    return value * vfloat<N>(static_cast<float>((w.width - 1) * (w.height - 1)));
}

// A point of the unit square and a warp's density there (per unit area): what inverting a
// warp gives (the uniform point sampling maps onto the given one) and what sampling gives.
template <int N>
struct RglWarpPoint {
    vfloat<N> x, y, density;
};

// The inverse of a warp at (x, y).

template <int N>
PATINA_INLINE RglWarpPoint<N> rgl_warp_invert(const RglWarpView& w, const RglParams<N>& params, vfloat<N> x,
                                            vfloat<N> y) {
    using F = vfloat<N>;
    using I = vint<N>;
    const F one(1.0f), half(0.5f);
    const int cells = w.height * w.width;
    const RglPatch<N> p = rgl_patch<N>(x, y, w.height, w.width);
    const F v00 = rgl_blend<N>(w.data, cells, params, p.node);
    const F v10 = rgl_blend<N>(w.data, cells, params, p.node + I(1));
    const F v01 = rgl_blend<N>(w.data, cells, params, p.node + I(w.width));
    const F v11 = rgl_blend<N>(w.data, cells, params, p.node + I(w.width + 1));
    const F c0 = (one - p.fy) * v00 + p.fy * v01;  // the density along the point's row, at its columns
    const F c1 = (one - p.fy) * v10 + p.fy * v11;
    RglWarpPoint<N> r;
    r.density = ((one - p.fx) * c0 + p.fx * c1) * F(static_cast<float>((w.width - 1) * (w.height - 1)));
    F ux = p.fx * (c0 + half * p.fx * (c1 - c0));
    ux = ux + (one - p.fy) * rgl_blend<N>(w.conditional, cells, params, p.node) +
         p.fy * rgl_blend<N>(w.conditional, cells, params, p.node + I(w.width));
    const I row_start = p.row * I(w.width);
    const F r0 = rgl_blend<N>(w.conditional, cells, params, row_start + I(w.width - 1));
    const F r1 = rgl_blend<N>(w.conditional, cells, params, row_start + I(2 * w.width - 1));
    r.x = ux / max((one - p.fy) * r0 + p.fy * r1, F(1e-30f));
    r.y = p.fy * (r0 + half * p.fy * (r1 - r0)) + rgl_blend<N>(w.marginal, w.height, params, p.row);
    return r;
}

PATINA_END_TARGET
