// A warp of an RGL material applied to uniform points, N lanes at a time
// (rgl_warp.Interpolant2D.sample is the double-precision reference): the row by the marginal
// CDF, the column by the row's conditional CDF (blended between the point's two rows), each
// inverted within its cell, where the density is linear. The searches are masked binary
// searches over CDF values blended across the incident angles: every lane walks its own
// path, the loop runs until the last lane is done, and a lane's result never depends on the
// others (width 1's bits at every width).
#pragma once

#include "brdf/rgl/rgl_grid.h"
#include "brdf/rgl/rgl_params.h"
#include "brdf/rgl/rgl_view.h"
#include "core/simd/simd.h"

PATINA_BEGIN_TARGET

namespace rgl_detail {
// The index i in [0, size - 2] with below(i) true and below(i + 1) false, below monotone
// in i (clamped at both ends), per lane.
template <int N, class Below>
PATINA_INLINE vint<N> find_interval(int size, Below below) {
    using I = vint<N>;
    I first(1), left(size - 2);
    for (vbool<N> active = left > I(0); any(active); active = left > I(0)) {
        const I half = left >> 1;
        const I middle = min(first + half, I(size - 1));
        const vbool<N> go_right = below(middle) & active;
        first = select(go_right, middle + I(1), first);
        left = select(active, select(go_right, left - (half + I(1)), half), left);
    }
    return min(max(first - I(1), I(0)), I(size - 2));
}

// t in [0, 1] with integral_0^t ((1 - s) a + s b) ds = u: the inverse CDF of a linear density.
template <int N>
PATINA_INLINE vfloat<N> solve_linear_density(vfloat<N> a, vfloat<N> b, vfloat<N> u) {
    using F = vfloat<N>;
    const vbool<N> flat = abs(a - b) < F(1e-4f) * (a + b);
    const F root = (a - sqrt_exact(max(a * a - F(2.0f) * u * (a - b), F(0.0f)))) / select(flat, F(1.0f), a - b);
    const F even = F(2.0f) * u / max(a + b, F(1e-30f));
    return clamp(select(flat, even, root), F(0.0f), F(1.0f));
}
}  // namespace rgl_detail

// The point the warp maps (ux, uy) onto, and the warp's density there.
template <int N>
PATINA_INLINE RglWarpPoint<N> rgl_warp_sample(const RglWarpView& w, const RglParams<N>& params, vfloat<N> ux,
                                           vfloat<N> uy) {
    using F = vfloat<N>;
    using I = vint<N>;
    using rgl_detail::solve_linear_density;
    const F one(1.0f);
    const int cells = w.height * w.width;
    const auto blend = [&](const float* table, int stride, I index) { return rgl_blend<N>(table, stride, params, index); };
    const I row = rgl_detail::find_interval<N>(w.height, [&](I k) { return blend(w.marginal, w.height, k) < uy; });
    uy = uy - blend(w.marginal, w.height, row);
    const I start = row * I(w.width);
    const F r0 = blend(w.conditional, cells, start + I(w.width - 1));
    const F r1 = blend(w.conditional, cells, start + I(2 * w.width - 1));
    const F fy = solve_linear_density<N>(r0, r1, uy);
    ux = ux * ((one - fy) * r0 + fy * r1);
    const auto conditional_at = [&](I k) {
        return (one - fy) * blend(w.conditional, cells, start + k) + fy * blend(w.conditional, cells, start + I(w.width) + k);
    };
    const I col = rgl_detail::find_interval<N>(w.width, [&](I k) { return conditional_at(k) < ux; });
    ux = ux - conditional_at(col);
    const I node = start + col;
    const F c0 = (one - fy) * blend(w.data, cells, node) + fy * blend(w.data, cells, node + I(w.width));
    const F c1 = (one - fy) * blend(w.data, cells, node + I(1)) + fy * blend(w.data, cells, node + I(w.width + 1));
    const F fx = solve_linear_density<N>(c0, c1, ux);
    RglWarpPoint<N> r;
    r.x = (to_float(col) + fx) * F(1.0f / static_cast<float>(w.width - 1));
    r.y = (to_float(row) + fy) * F(1.0f / static_cast<float>(w.height - 1));
    r.density = ((one - fx) * c0 + fx * c1) * F(static_cast<float>((w.width - 1) * (w.height - 1)));
    return r;
}

PATINA_END_TARGET
