// Rasterizing a projected surfel (or a silhouette's shadow) into mask rows: the convex hull
// of its points in texel coordinates (u R, v R), then, row by row, the span of texels whose
// centre is inside, as one 128-bit word. The hull makes any corner order and any slightly
// bent projection one convex region; its edges are straight in the square, the projection's
// are slightly curved, which is why a surfel is projected by its corners and edge midpoints.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/simd/target.h"
#include "render/cache/bit_mask.h"

PATINA_BEGIN_TARGET
namespace cache {

constexpr int kMaxHullPoints = 8;

// Sorts n points by x, then y, from (px, py) into (sx, sy): each point goes to its rank, the
// number of points before it (ties by index), counted without a branch. The hull's index sort
// (std::sort) was a tenth of the reprojection's time on the room, its comparisons' branches
// unpredictable (docs/radiance-cache.md, "The cache's own stages cheaper"). The order is a
// sort's like any other, and points that compare equal are equal, so the hull is the same.
PATINA_INLINE void sort_points(const float* px, const float* py, int n, float* sx, float* sy) {
    for (int i = 0; i < n; ++i) {
        int rank = 0;
        for (int j = 0; j < n; ++j) {
            const bool same_x = px[j] == px[i], same_y = py[j] == py[i];
            rank += (px[j] < px[i]) | (same_x & ((py[j] < py[i]) | (same_y & (j < i))));
        }
        sx[rank] = px[i], sy[rank] = py[i];
    }
}

// The convex hull of n <= kMaxHullPoints points, counter-clockwise (Andrew's monotone chain)
// into hx, hy; returns its size (0 when a point is not finite).
PATINA_INLINE int convex_hull(const float* px, const float* py, int n, float* hx, float* hy) {
    for (int i = 0; i < n; ++i)
        if (!std::isfinite(px[i]) || !std::isfinite(py[i])) return 0;
    float sx[kMaxHullPoints], sy[kMaxHullPoints];
    sort_points(px, py, n, sx, sy);
    // the chain holds the points themselves, not their indices: one dependent load less in
    // each turn, the chain a fifth of the reprojection's own time on the room
    float cx[2 * kMaxHullPoints], cy[2 * kMaxHullPoints];
    auto turn = [&](int k, int i) {  // of chain points k - 2, k - 1 and sorted point i
        return (cx[k - 1] - cx[k - 2]) * (sy[i] - cy[k - 2]) - (cy[k - 1] - cy[k - 2]) * (sx[i] - cx[k - 2]);
    };
    int k = 0;
    auto push = [&](int i) { cx[k] = sx[i], cy[k] = sy[i], ++k; };
    for (int i = 0; i < n; ++i) {  // lower chain
        while (k >= 2 && turn(k, i) <= 0) --k;
        push(i);
    }
    for (int i = n - 2, t = k + 1; i >= 0; --i) {  // upper chain
        while (k >= t && turn(k, i) <= 0) --k;
        push(i);
    }
    const int m = std::max(k - 1, 0);
    std::copy(cx, cx + m, hx);
    std::copy(cy, cy + m, hy);
    return m;
}

// row(y, span) for each row y of an R x R grid that the convex hull of the n points (texel
// coordinates) covers, span holding the texels whose centres are inside it.
template <class RowFn>
PATINA_INLINE void raster_convex(const float* px, const float* py, int n, int resolution, RowFn row) {
    float hx[kMaxHullPoints], hy[kMaxHullPoints];
    const int m = convex_hull(px, py, n, hx, hy);
    if (m < 3) return;
    float ylo = hy[0], yhi = hy[0];
    for (int i = 1; i < m; ++i) ylo = std::min(ylo, hy[i]), yhi = std::max(yhi, hy[i]);
    const int y0 = std::max(0, static_cast<int>(std::ceil(ylo - 0.5f)));
    const int y1 = std::min(resolution, static_cast<int>(std::floor(yhi - 0.5f)) + 1);
    for (int y = y0; y < y1; ++y) {
        const float yc = static_cast<float>(y) + 0.5f;
        float xlo = -1e30f, xhi = 1e30f;
        bool empty = false;
        for (int i = 0; i < m && !empty; ++i) {
            const int j = i + 1 == m ? 0 : i + 1;
            const float ex = hx[j] - hx[i], ey = hy[j] - hy[i];
            // inside (counter-clockwise): ex (yc - y_i) - ey (x - x_i) >= 0
            const float k = ex * (yc - hy[i]) + ey * hx[i];
            if (ey > 0) {
                xhi = std::min(xhi, k / ey);
            } else if (ey < 0) {
                xlo = std::max(xlo, k / ey);
            } else if (ex * (yc - hy[i]) < 0) {
                empty = true;
            }
        }
        if (empty || !(xlo <= xhi)) continue;
        const float a = std::max(xlo - 0.5f, -1.0f), b = std::min(xhi - 0.5f, static_cast<float>(resolution));
        const int x0 = std::max(0, static_cast<int>(std::ceil(a)));
        const int x1 = std::min(resolution, static_cast<int>(std::floor(b)) + 1);
        if (x0 < x1) row(y, span_bits(x0, x1));
    }
}

}  // namespace cache
PATINA_END_TARGET
