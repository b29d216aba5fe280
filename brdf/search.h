// Coherent binary search on an irregular axis, N lanes at a time (thesis, ch. 2).
//
// While every active lane falls on the same side of the middle knot, the search
// walks one branch with a broadcast knot, exactly like a scalar binary search.
// When the lanes disagree, both branches are walked with the inactive lanes masked,
// in one of two ways:
//   SplitWalk::Sequential  the thesis's scheme: one branch after the other, each a
//                          coherent search of its own lanes (recursively);
//   SplitWalk::Masked      Patina's default: all lanes at once, each down its own
//                          branch, one masked gather of middle knots per level.
// The sequential walk makes incoherent lanes cost one full, mispredicted scalar
// search each, slower than scalar code on random input (0.6x at width 4, 0.7x at
// width 8); the masked walk has no data-dependent branches (2.5x and 4.6x), and is
// also a little faster on coherent input, where lanes split only near the leaves.
// `patina bench` measures both. At N = 1 there is one lane, no split, and the search
// is an ordinary binary search.
#pragma once

#include "core/simd/simd.h"

PATINA_BEGIN_TARGET

enum class SplitWalk { Sequential, Masked };

namespace search_detail {
// Every active lane walks its own branch of [lo, hi] at the same time: per level one
// gather of the lanes' middle knots and a masked update of their bounds.
template <int N>
PATINA_INLINE void masked_descent(const float* knots, int lo, int hi, vfloat<N> x, vbool<N> active, vint<N>& cell) {
    vint<N> l(lo), h(hi);
    for (int widest = hi - lo; widest > 1; widest = (widest + 1) >> 1) {
        const vint<N> mid = (l + h) >> 1;
        const vbool<N> right = x >= gather(knots, mid);
        l = select(right, mid, l);
        h = select(right, h, mid);
    }
    cell = select(active, l, cell);
}

// For the active lanes (bit mask `lanes`, vector mask `active`), narrows [lo, hi] (knot
// indices; the answer is a cell in [lo, hi - 1]) and writes the cell into `cell`.
// One movemask per level decides: all active lanes right, all left, or split.
template <int N, SplitWalk Walk>
inline void search_range(const float* knots, int lo, int hi, vfloat<N> x, vbool<N> active, int lanes,
                         vint<N>& cell) {
    while (hi - lo > 1) {
        const int mid = (lo + hi) >> 1;
        const vbool<N> right = x >= vfloat<N>(knots[mid]);
        const int go_right = movemask(right) & lanes;
        if (go_right == 0) {
            hi = mid;
        } else if (go_right == lanes) {
            lo = mid;
        } else if constexpr (Walk == SplitWalk::Masked) {
            masked_descent<N>(knots, lo, hi, x, active, cell);
            return;
        } else {
            search_range<N, Walk>(knots, mid, hi, x, right & active, go_right, cell);
            active = andnot(right, active);
            lanes &= ~go_right;
            hi = mid;
        }
    }
    cell = select(active, vint<N>(lo), cell);
}
}  // namespace search_detail

// Returns, for each active lane, the cell i in [0, n - 2] with knots[i] <= x < knots[i + 1];
// x below the axis gives 0, x at or above the last knot gives n - 2, NaN gives 0.
// Inactive lanes give 0. Requires n >= 2 and strictly increasing knots.
template <int N, SplitWalk Walk = SplitWalk::Masked>
PATINA_INLINE vint<N> coherent_search(const float* knots, int n, vfloat<N> x, vbool<N> active) {
    vint<N> cell(0);
    const int lanes = movemask(active);
    if (lanes) search_detail::search_range<N, Walk>(knots, 0, n - 1, x, active, lanes, cell);
    return cell;
}

PATINA_END_TARGET
