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

// The cell and the fraction within it along one axis, clamped to the axis; `shared`: every lane
// in one cell. The knots are read by lookup_cells: a broadcast when the lanes share a cell (a
// packet of neighbouring sensors towards one luminaire nearly always does), a pick from
// registers when their cells are near, a gather only otherwise -- the same knots either way, so
// the same bits. The lighting bench's candela and responses without shadows (10^5 sensors x 20
// luminaires, width 8, one thread): 0.035 s with gathers, 0.029 s so (least of 9, docs/bench.md).
template <int W>
PATINA_INLINE void locate(const float* knots, int n, vfloat<W> x, vint<W>& cell, vfloat<W>& t, bool& shared) {
    using FW = vfloat<W>;
    if (n == 1) {
        cell = vint<W>(0);
        t = FW(0.0f);
        shared = true;
        return;
    }
    const FW xc = clamp(x, FW(knots[0]), FW(knots[n - 1]));
    const vbool<W> every = FW(0.0f) == FW(0.0f);
    const Cells<W> c = coherent_search_cells<W>(knots, n, xc, every);
    cell = c.cell;
    shared = c.hi - c.lo == 1;
    // knots[cell] and knots[cell + 1]: the cells index the knots from 0 and from 1
    const FW k0 = lookup_cells<W>(knots, n - 1, c, every), k1 = lookup_cells<W>(knots + 1, n - 1, c, every);
    t = clamp((xc - k0) / (k1 - k0), FW(0.0f), FW(1.0f));
}

// The four corners' values of the lanes' cells: broadcasts when every lane lies in one cell.
template <int W>
PATINA_INLINE void corners(const Grid2View& g, vint<W> ix, vint<W> iy, bool shared, vfloat<W>* v) {
    using IW = vint<W>;
    const int step_x = g.nx > 1 ? g.ny : 0, step_y = g.ny > 1 ? 1 : 0;
    if (shared) {
        const float* at = g.values + lane(ix, 0) * g.ny + lane(iy, 0);
        for (int k = 0; k < 4; ++k) v[k] = vfloat<W>(at[(k >> 1) * step_x + (k & 1) * step_y]);
        return;
    }
    const IW row0 = ix * IW(g.ny), row1 = row0 + IW(step_x), iy1 = iy + IW(step_y);
    v[0] = gather(g.values, row0 + iy);
    v[1] = gather(g.values, row0 + iy1);
    v[2] = gather(g.values, row1 + iy);
    v[3] = gather(g.values, row1 + iy1);
}

template <int W>
PATINA_INLINE vfloat<W> eval(const Grid2View& g, vfloat<W> x, vfloat<W> y) {
    using FW = vfloat<W>;
    using IW = vint<W>;
    IW ix, iy;
    FW tx, ty;
    bool shared_x, shared_y;
    locate<W>(g.x, g.nx, x, ix, tx, shared_x);
    locate<W>(g.y, g.ny, y, iy, ty, shared_y);
    FW v[4];  // v00, v01, v10, v11
    corners<W>(g, ix, iy, shared_x && shared_y, v);
    // (1 - t) a + t b, not a + t (b - a): exact at both ends of a cell, so the table's own
    // values come back at every knot, the last included
    const FW sy = FW(1.0f) - ty, sx = FW(1.0f) - tx;
    const FW a = madd(ty, v[1], sy * v[0]), b = madd(ty, v[3], sy * v[2]);
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
