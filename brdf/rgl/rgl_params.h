// The incident-angle parameters of an RGL material's tables, N lanes at a time: each lane's
// cell on the theta_i and phi_i axes (the coherent binary search: coherent directions share
// their cells and walk one path) and the weights of its up to four corners, by which every
// parametrised lookup (the warps, the values) blends the grids of neighbouring incident angles,
// linearly per axis as rgl_warp.Interpolant2D does (outside an axis: clamped to its ends).
#pragma once

#include "brdf/rgl/rgl_view.h"
#include "brdf/search.h"

PATINA_BEGIN_TARGET

template <int N>
struct RglParams {
    int count = 1;          // corners: 1, 2 or 4 (an axis with one value has one)
    vint<N> slice[4];       // grid index phi * theta_count + theta of each corner
    vfloat<N> weight[4];
};

// Where the previous block's searches ended (SearchHint), per axis.
struct RglHints {
    SearchHint theta, phi;
};

namespace rgl_detail {
// An axis's one or two ends around x, as (index, weight): the lower cell by the coherent
// search and the weight of its upper end, clamped to [0, 1]; an axis of one value has one end.
// Returns the number of ends.
template <int N>
PATINA_INLINE int axis_ends(const float* knots, int count, vfloat<N> x, vbool<N> active, SearchHint& hint,
                            vint<N> (&index)[2], vfloat<N> (&weight)[2]) {
    using F = vfloat<N>;
    index[0] = index[1] = vint<N>(0);
    weight[0] = F(1.0f);
    weight[1] = F(0.0f);
    if (count < 2) return 1;
    const Cells<N> cells = coherent_search_cells<N>(knots, count, x, active, hint);
    const F low = lookup_cells<N>(knots, count, cells, active);
    const F high = lookup_cells<N>(knots + 1, count - 1, cells, active);
    const F upper = clamp((x - low) / (high - low), F(0.0f), F(1.0f));
    index[0] = cells.cell;
    index[1] = cells.cell + vint<N>(1);
    weight[0] = F(1.0f) - upper;
    weight[1] = upper;
    return 2;
}
}  // namespace rgl_detail

template <int N>
PATINA_INLINE RglParams<N> rgl_params(const RglView& v, vfloat<N> phi_i, vfloat<N> theta_i, vbool<N> active,
                                      RglHints& hints) {
    vint<N> phi_index[2], theta_index[2];
    vfloat<N> phi_weight[2], theta_weight[2];
    const int phi_ends = rgl_detail::axis_ends<N>(v.phi_i, v.phi_count, phi_i, active, hints.phi, phi_index, phi_weight);
    const int theta_ends =
        rgl_detail::axis_ends<N>(v.theta_i, v.theta_count, theta_i, active, hints.theta, theta_index, theta_weight);
    RglParams<N> p;
    p.count = 0;
    for (int a = 0; a < phi_ends; ++a)
        for (int b = 0; b < theta_ends; ++b) {
            p.slice[p.count] = phi_index[a] * vint<N>(v.theta_count) + theta_index[b];
            p.weight[p.count] = phi_weight[a] * theta_weight[b];
            ++p.count;
        }
    return p;
}

// sum over the corners of weight * table[slice * stride + index]: a grid value blended
// over the incident angles.
template <int N>
PATINA_INLINE vfloat<N> rgl_blend(const float* table, int stride, const RglParams<N>& p, vint<N> index) {
    vfloat<N> sum = p.weight[0] * gather(table, p.slice[0] * vint<N>(stride) + index);
    for (int k = 1; k < p.count; ++k) sum = madd(p.weight[k], gather(table, p.slice[k] * vint<N>(stride) + index), sum);
    return sum;
}

PATINA_END_TARGET
