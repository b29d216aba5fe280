// Coherent binary search on an irregular axis, N lanes at a time (thesis, ch. 2).
//
// While every active lane falls on the same side of the middle knot, the search
// walks one branch with a broadcast knot, exactly like a scalar binary search.
// When the lanes disagree, it walks both branches one after the other, each
// with the other lanes masked off. Coherent lanes (neighbouring pixels) thus
// cost one scalar search; random lanes cost at most one search per lane. At
// N = 1 this is an ordinary binary search.
#pragma once

#include "core/simd/simd.h"

PATINA_BEGIN_TARGET

namespace search_detail {
// For the active lanes, narrows [lo, hi] (knot indices, the answer is a cell in
// [lo, hi - 1]) and writes the cell into `cell`.
template <int N>
inline void search_range(const float* knots, int lo, int hi, vfloat<N> x, vbool<N> active, vint<N>& cell) {
    while (hi - lo > 1) {
        const int mid = (lo + hi) >> 1;
        const vbool<N> right = x >= vfloat<N>(knots[mid]);
        const vbool<N> go_right = right & active;
        if (none(go_right)) {
            hi = mid;
            continue;
        }
        const vbool<N> go_left = andnot(right, active);
        if (none(go_left)) {
            lo = mid;
            continue;
        }
        search_range<N>(knots, mid, hi, x, go_right, cell);
        active = go_left;
        hi = mid;
    }
    cell = select(active, vint<N>(lo), cell);
}
}  // namespace search_detail

// Returns, for each active lane, the cell i in [0, n - 2] with knots[i] <= x < knots[i + 1];
// x below the axis gives 0, x at or above the last knot gives n - 2, NaN gives 0.
// Inactive lanes give 0. Requires n >= 2 and strictly increasing knots.
template <int N>
PATINA_INLINE vint<N> coherent_search(const float* knots, int n, vfloat<N> x, vbool<N> active) {
    vint<N> cell(0);
    if (any(active)) search_detail::search_range<N>(knots, 0, n - 1, x, active, cell);
    return cell;
}

PATINA_END_TARGET
