// A 2-D table on an irregular tensor grid, W points at a time (included by
// integrator_w{1,4,8,16}.cpp): the goniometric light's candela table over (C-plane, gamma)
// angles. Evaluated like the BRDF tables: per axis the coherent binary search of
// brdf/search.h (one search for both; not a copy), then bilinear interpolation of the cell's
// corners. Coordinates outside an axis clamp to its ends. Templated on the width W (not just
// the unit's N) because the light selection evaluates one point at W = 1 where the light
// sampling evaluates N: each lane's value is the same bits at every width.
#pragma once

#include "brdf/search.h"
#include "core/simd/kernel_width.h"
#include "render/lights/grid2.h"

PATINA_BEGIN_TARGET
namespace render_detail {
namespace grid2_w {
using namespace kernel_width;

// The cell and the fraction within it along one axis, clamped to the axis.
template <int W>
PATINA_INLINE void locate(const float* knots, int n, vfloat<W> x, vint<W>& cell, vfloat<W>& t) {
    using FW = vfloat<W>;
    using IW = vint<W>;
    if (n == 1) {
        cell = IW(0);
        t = FW(0.0f);
        return;
    }
    const FW xc = clamp(x, FW(knots[0]), FW(knots[n - 1]));
    cell = coherent_search<W>(knots, n, xc, FW(0.0f) == FW(0.0f));
    const FW k0 = gather(knots, cell), k1 = gather(knots, cell + IW(1));
    t = clamp((xc - k0) / (k1 - k0), FW(0.0f), FW(1.0f));
}

template <int W>
PATINA_INLINE vfloat<W> eval(const Grid2View& g, vfloat<W> x, vfloat<W> y) {
    using FW = vfloat<W>;
    using IW = vint<W>;
    IW ix, iy;
    FW tx, ty;
    locate<W>(g.x, g.nx, x, ix, tx);
    locate<W>(g.y, g.ny, y, iy, ty);
    const IW ix1 = g.nx > 1 ? ix + IW(1) : ix, iy1 = g.ny > 1 ? iy + IW(1) : iy;
    const IW row0 = ix * IW(g.ny), row1 = ix1 * IW(g.ny);
    const FW v00 = gather(g.values, row0 + iy), v01 = gather(g.values, row0 + iy1);
    const FW v10 = gather(g.values, row1 + iy), v11 = gather(g.values, row1 + iy1);
    // (1 - t) a + t b, not a + t (b - a): exact at both ends of a cell, so the table's own
    // values come back at every knot, the last included
    const FW sy = FW(1.0f) - ty, sx = FW(1.0f) - tx;
    const FW a = madd(ty, v01, sy * v00), b = madd(ty, v11, sy * v10);
    return madd(tx, b, sx * a);
}

inline void eval_array(const Grid2View& g, const float* x, const float* y, float* out, size_t n) {
    for_blocks(n, [&](size_t i, int lanes) {
        store_lanes(out, i, lanes, eval<N>(g, load_lanes(x, i, lanes), load_lanes(y, i, lanes)));
    });
}

}  // namespace grid2_w
}  // namespace render_detail
PATINA_END_TARGET
