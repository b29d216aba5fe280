// A 2-D table on an irregular tensor grid, N points at a time (included by
// integrator_w{1,4,8}.cpp): the goniometric light's candela table over (C-plane, gamma) angles.
// Evaluated like the BRDF tables: per axis the coherent binary search of brdf/search.h
// (one search for both; not a copy), then bilinear interpolation of the cell's corners.
// Coordinates outside an axis clamp to its ends.
#pragma once

#include "brdf/search.h"
#include "core/simd/kernel_width.h"
#include "render/grid2.h"

PATINA_BEGIN_TARGET
namespace render_detail {
namespace grid2_w {
using namespace kernel_width;

// The cell and the fraction within it along one axis, clamped to the axis.
PATINA_INLINE void locate(const float* knots, int n, F x, I& cell, F& t) {
    if (n == 1) {
        cell = I(0);
        t = F(0.0f);
        return;
    }
    const F xc = clamp(x, F(knots[0]), F(knots[n - 1]));
    cell = coherent_search<N>(knots, n, xc, F(0.0f) == F(0.0f));
    const F k0 = gather(knots, cell), k1 = gather(knots, cell + I(1));
    t = clamp((xc - k0) / (k1 - k0), F(0.0f), F(1.0f));
}

PATINA_INLINE F eval(const Grid2View& g, F x, F y) {
    I ix, iy;
    F tx, ty;
    locate(g.x, g.nx, x, ix, tx);
    locate(g.y, g.ny, y, iy, ty);
    const I ix1 = g.nx > 1 ? ix + I(1) : ix, iy1 = g.ny > 1 ? iy + I(1) : iy;
    const I row0 = ix * I(g.ny), row1 = ix1 * I(g.ny);
    const F v00 = gather(g.values, row0 + iy), v01 = gather(g.values, row0 + iy1);
    const F v10 = gather(g.values, row1 + iy), v11 = gather(g.values, row1 + iy1);
    // (1 - t) a + t b, not a + t (b - a): exact at both ends of a cell, so the table's own
    // values come back at every knot, the last included
    const F sy = F(1.0f) - ty, sx = F(1.0f) - tx;
    const F a = madd(ty, v01, sy * v00), b = madd(ty, v11, sy * v10);
    return madd(tx, b, sx * a);
}

inline void eval_array(const Grid2View& g, const float* x, const float* y, float* out, size_t n) {
    for_blocks(n, [&](size_t i, int lanes) {
        store_lanes(out, i, lanes, eval(g, load_lanes(x, i, lanes), load_lanes(y, i, lanes)));
    });
}

}  // namespace grid2_w
}  // namespace render_detail
PATINA_END_TARGET
