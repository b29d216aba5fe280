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
//
// At widths 8 and 16 the masked walk also keeps knots in registers. Coherent lanes split
// low in the tree, their cells a few knots apart: when all of them lie in the 2N knots
// around the split, those are loaded once into two registers and each level's middle knots
// are picked from them (permute2: one vpermt2ps at width 16) instead of gathered, one load a
// lane; the next block starts from that window when its lanes lie in it too (SearchHint),
// skipping the walk from the root; and the cells' own values (knots, cell widths) come from
// the same window (lookup_cells). On the AVX-512 machine of December 2026 a 16-lane gather
// costs about as much as 16 loads, so this took the MERL evaluator's search from 60 % of
// its width-16 time to 35 % (docs/performance.md, "Width 16 on a real AVX-512 CPU"). The
// cells are the same bits either way: a lane's cell is the low end of the range plus the
// number of knots inside it at or below x, whichever range holds it.
#pragma once

#include <algorithm>

#include "core/simd/simd.h"

PATINA_BEGIN_TARGET

enum class SplitWalk { Sequential, Masked };

// The cells a search found and the knots they lie between: every active lane's cell is in
// [lo, hi - 1]. With it, lookups of per-cell arrays read registers instead of memory
// (lookup_cells): coherent lanes have a narrow range.
template <int N>
struct Cells {
    vint<N> cell;
    int lo, hi;
};

// Where the previous block's search ended, for the next block's to start from: coherent blocks
// follow each other closely (row-scanned pixels, sorted samples).
struct SearchHint {
    int lo = 0, hi = 0;  // knots; empty (lo == hi) before the first search
};

// Widths whose vector types have permute2 (a gather from a 2N-float window in two registers).
template <int N>
inline constexpr bool kWindowed = N == 8 || N == 16;

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

// The masked descent when the knots it can read, lo + 1 .. hi - 1, lie in the 2N knots from
// `start`: they are loaded once into two registers and each level's middle knots are picked
// from them (permute2), not gathered. The same levels, bounds and cells as masked_descent:
// the split happens low in the tree on coherent input, where the range is narrow.
template <int N>
PATINA_INLINE void window_descent(const float* knots, int start, int lo, int hi, vfloat<N> x, vbool<N> active,
                                  vint<N>& cell) {
    const vfloat<N> w0 = load_n<N>(knots + start), w1 = load_n<N>(knots + start + N);
    const vint<N> offset(start);
    vint<N> l(lo - start), h(hi - start);
    for (int widest = hi - lo; widest > 1; widest = (widest + 1) >> 1) {
        const vint<N> mid = (l + h) >> 1;
        const vbool<N> right = x >= permute2(w0, w1, mid);
        l = select(right, mid, l);
        h = select(right, h, mid);
    }
    cell = select(active, l + offset, cell);
}

// Whether every active lane (bit mask `lanes`) whose cell lies in [lo, hi - 1] has it in
// [s, e - 1] (lo <= s < e <= hi): x >= knots[s] unless s = lo, x < knots[e] unless e = hi.
// A NaN lane, which belongs at lo, fails the first test.
template <int N>
PATINA_INLINE bool lanes_within(const float* knots, int lo, int hi, int s, int e, vfloat<N> x, vbool<N> active,
                                int lanes) {
    vbool<N> inside = active;
    if (s > lo) inside = inside & (x >= vfloat<N>(knots[s]));
    if (e < hi) inside = inside & (x < vfloat<N>(knots[e]));
    return movemask(inside) == lanes;
}

// The active lanes split at knot `mid` of [lo, hi]. Coherent lanes' cells are still close:
// if they all lie within the 2N knots [s, e] around mid, the descent from [s, e] finds the
// cells the one from [lo, hi] would (a lane's cell is the range's low end plus the number of
// knots inside it at or below x), with the knots in registers. Returns false, having done
// nothing, when a lane lies outside.
template <int N>
PATINA_INLINE bool window_split(const float* knots, int n, int lo, int mid, int hi, vfloat<N> x, vbool<N> active,
                                int lanes, Cells<N>& range) {
    const int s = std::max(lo, std::min(mid - N, hi - 2 * N));
    const int e = std::min(hi, s + 2 * N);
    if (!lanes_within<N>(knots, lo, hi, s, e, x, active, lanes)) return false;
    window_descent<N>(knots, std::min(s, n - 2 * N), s, e, x, active, range.cell);
    range.lo = s;
    range.hi = e;
    return true;
}

// For the active lanes (bit mask `lanes`, vector mask `active`), narrows [lo, hi] (knot
// indices into n knots; the answer is a cell in [lo, hi - 1]) and writes the cells into
// range.cell and the knots they lie between (where the lanes first split, or the window)
// into range.lo, range.hi. One movemask per level decides: all active lanes right, all left,
// or split.
template <int N, SplitWalk Walk>
inline void search_range(const float* knots, int n, int lo, int hi, vfloat<N> x, vbool<N> active, int lanes,
                         Cells<N>& range) {
    bool split = false;
    while (hi - lo > 1) {
        const int mid = (lo + hi) >> 1;
        const vbool<N> right = x >= vfloat<N>(knots[mid]);
        const int go_right = movemask(right) & lanes;
        if (go_right == 0) {
            hi = mid;
        } else if (go_right == lanes) {
            lo = mid;
        } else if constexpr (Walk == SplitWalk::Masked) {
            if constexpr (kWindowed<N>) {
                if (n >= 2 * N && window_split<N>(knots, n, lo, mid, hi, x, active, lanes, range)) return;
            }
            range.lo = lo;
            range.hi = hi;
            masked_descent<N>(knots, lo, hi, x, active, range.cell);
            return;
        } else {
            if (!split) {
                range.lo = lo;
                range.hi = hi;
                split = true;
            }
            Cells<N> inner{range.cell, 0, 0};
            search_range<N, Walk>(knots, n, mid, hi, x, right & active, go_right, inner);
            range.cell = inner.cell;
            active = andnot(right, active);
            lanes &= ~go_right;
            hi = mid;
        }
    }
    range.cell = select(active, vint<N>(lo), range.cell);
    if (!split) {
        range.lo = lo;
        range.hi = hi;
    }
}
}  // namespace search_detail

// Returns, for each active lane, the cell i in [0, n - 2] with knots[i] <= x < knots[i + 1];
// x below the axis gives 0, x at or above the last knot gives n - 2, NaN gives 0.
// Inactive lanes give 0. Requires n >= 2 and strictly increasing knots.
template <int N, SplitWalk Walk = SplitWalk::Masked>
PATINA_INLINE Cells<N> coherent_search_cells(const float* knots, int n, vfloat<N> x, vbool<N> active) {
    Cells<N> c{vint<N>(0), 0, 1};
    const int lanes = movemask(active);
    if (lanes) search_detail::search_range<N, Walk>(knots, n, 0, n - 1, x, active, lanes, c);
    return c;
}

// coherent_search_cells, starting from the hint: when the previous block's range was narrow and
// every active lane lies in the 2N knots around it, the window descent alone finds their cells
// (no walk from the root, none of its branches); otherwise the search from the root, whose
// range becomes the hint. The cells are the same either way.
template <int N, SplitWalk Walk = SplitWalk::Masked>
PATINA_INLINE Cells<N> coherent_search_cells(const float* knots, int n, vfloat<N> x, vbool<N> active,
                                             SearchHint& hint) {
    if constexpr (kWindowed<N>) {
        const int lanes = movemask(active);
        // the lanes of the last block searched from the root shared one cell, and these lie in
        // it too (an axis that varies slowly, or not at all, over the blocks): no descent, and
        // the lookups are broadcasts
        if (hint.hi - hint.lo == 1 && lanes && search_detail::lanes_within<N>(knots, 0, n - 1, hint.lo, hint.hi, x,
                                                                               active, lanes))
            return Cells<N>{select(active, vint<N>(hint.lo), vint<N>(0)), hint.lo, hint.hi};
        // an empty hint (the first block) or a wide one (the last block's lanes split high in
        // the tree: incoherent) is not tried
        if (hint.hi > hint.lo && hint.hi - hint.lo <= 2 * N && n > 2 * N && lanes) {
            const int s = std::min(std::max((hint.lo + hint.hi) / 2 - N, 0), n - 1 - 2 * N), e = s + 2 * N;
            if (search_detail::lanes_within<N>(knots, 0, n - 1, s, e, x, active, lanes)) {
                Cells<N> c{vint<N>(0), s, e};
                search_detail::window_descent<N>(knots, s, s, e, x, active, c.cell);
                return c;
            }
        }
    }
    // (lanes that share a cell never split: the range a search from the root gives them is
    // that cell, the hint the first test above takes)
    const Cells<N> c = coherent_search_cells<N, Walk>(knots, n, x, active);
    hint.lo = c.lo;
    hint.hi = c.hi;
    return c;
}

template <int N, SplitWalk Walk = SplitWalk::Masked>
PATINA_INLINE vint<N> coherent_search(const float* knots, int n, vfloat<N> x, vbool<N> active) {
    return coherent_search_cells<N, Walk>(knots, n, x, active).cell;
}

// a[cell] for each active lane of c, a[0] for the others (whose cell is 0): what
// gather(a, c.cell) gives, for an array of `len` floats indexed by cell or knot. A broadcast
// when the lanes share one cell, a pick from 2N floats in registers (permute2) when their
// range fits, a gather otherwise.
template <int N>
PATINA_INLINE vfloat<N> lookup_cells(const float* a, int len, const Cells<N>& c, vbool<N> active) {
    if constexpr (N == 1) {
        return a[c.cell];
    } else {
        if (c.hi - c.lo == 1) return select(active, vfloat<N>(a[c.lo]), vfloat<N>(a[0]));
        if constexpr (kWindowed<N>) {
            if (c.hi - c.lo <= 2 * N && len >= 2 * N) {
                const int start = std::min(c.lo, len - 2 * N);
                const vfloat<N> window_lo = load_n<N>(a + start), window_hi = load_n<N>(a + start + N);
                const vfloat<N> picked = permute2(window_lo, window_hi, c.cell - vint<N>(start));
                return select(active, picked, vfloat<N>(a[0]));
            }
        }
        return gather(a, c.cell);
    }
}

PATINA_END_TARGET
