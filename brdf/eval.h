// The tabulated-BRDF evaluator, written once for every SIMD width.
//
// For N direction pairs in the surface's local frame (z = normal):
//   1. directions -> the table's angles, with the fast inverse trigonometry;
//   2. per axis, the coherent binary search finds the cell and its fraction
//      (angles outside an axis clamp to its ends);
//   3. multilinear interpolation of the 2^D cell corners, channel by channel.
// Pairs with either direction at or below the horizon give 0. Missing grid
// points (coverage 0) get no weight; the others are renormalized, and a cell
// with no measured corner gives 0.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "brdf/search.h"
#include "brdf/table.h"
#include "core/constants.h"
#include "core/simd/fastmath.h"
#include "core/simd/weighted_rows.h"
#include "core/vec3.h"

PATINA_BEGIN_TARGET

// Loads N directions from an (n, 3) row-major array.
template <int N>
PATINA_INLINE Vec3<vfloat<N>> load_dirs(const float* p) {
    Vec3<vfloat<N>> d;
    load_xyz(p, d.x, d.y, d.z);
    return d;
}

// The inverse trigonometry the evaluator uses: Patina's fast SIMD polynomials...
struct FastTrig {
    template <class F>
    static PATINA_INLINE F acos(F x) { return fast_acos(x); }
    template <class F>
    static PATINA_INLINE F atan2(F y, F x) { return fast_atan2(y, x); }
};
// ...or, at width 1 only, the C library's: the straightforward scalar evaluator that
// `patina bench` also measures against (what a scalar implementation without SIMD math
// would cost, as in the thesis's comparisons).
struct LibmTrig {
    static PATINA_INLINE float acos(float x) { return std::acos(x); }
    static PATINA_INLINE float atan2(float y, float x) { return std::atan2(y, x); }
};

namespace eval_detail {
template <int N, class Trig>
PATINA_INLINE vfloat<N> acos_clamped(vfloat<N> c) {
    return Trig::acos(clamp(c, vfloat<N>(-1.0f), vfloat<N>(1.0f)));
}

// Rusinkiewicz half/difference angles, computed without forward trigonometry:
// rotating wi by -phi_h about z and by -theta_h about y takes cos/sin of both angles
// straight from h. phi_d = atan2(ty, dx) of the rotated wi; both arguments carry a
// factor 1/sin(theta_h) that atan2 ignores, so they are used scaled by sin(theta_h):
// no division and no square root for it. At the pole (h = n) phi_h is taken as 0,
// as the MERL reference code does.
template <int N, class Trig>
PATINA_INLINE void halfdiff_coords(const Vec3<vfloat<N>>& wi, const Vec3<vfloat<N>>& wo, uint32_t symmetry,
                                   vfloat<N>* coord) {
    using F = vfloat<N>;
    F hx = wi.x + wo.x, hy = wi.y + wo.y, hz = wi.z + wo.z;
    const F inv_len = F(1.0f) / sqrt_exact(hx * hx + hy * hy + hz * hz);
    hx = hx * inv_len;
    hy = hy * inv_len;
    hz = hz * inv_len;
    coord[0] = acos_clamped<N, Trig>(hz);
    coord[1] = acos_clamped<N, Trig>(wi.x * hx + wi.y * hy + wi.z * hz);
    const F r2 = hx * hx + hy * hy;  // sin^2(theta_h)
    const vbool<N> tilted = r2 > F(1e-14f);
    const F y = select(tilted, hx * wi.y - hy * wi.x, wi.y);
    const F x = select(tilted, hz * (hx * wi.x + hy * wi.y) - r2 * wi.z, hz * wi.x);
    F phi_d = Trig::atan2(y, x);
    if (symmetry & kSymReciprocity) phi_d = select(phi_d < F(0.0f), phi_d + F(kPi), phi_d);
    if (symmetry & kSymPhiMirror) {
        phi_d = abs(phi_d);
        phi_d = select(phi_d > F(kHalfPi), F(kPi) - phi_d, phi_d);
    }
    coord[2] = phi_d;
}

template <int N, class Trig>
PATINA_INLINE void isotropic_coords(const Vec3<vfloat<N>>& wi, const Vec3<vfloat<N>>& wo, uint32_t symmetry,
                                    vfloat<N>* coord) {
    using F = vfloat<N>;
    F ti = acos_clamped<N, Trig>(wi.z), to = acos_clamped<N, Trig>(wo.z);
    if (symmetry & kSymReciprocity) {
        const vbool<N> swap = ti > to;
        const F lo = select(swap, to, ti);
        to = select(swap, ti, to);
        ti = lo;
    }
    const F cross = abs(wi.x * wo.y - wi.y * wo.x);
    const F dot = wi.x * wo.x + wi.y * wo.y;
    coord[0] = ti;
    coord[1] = to;
    coord[2] = Trig::atan2(cross, dot);  // in [0, pi]: the phi mirror of isotropy
}

template <int N, class Trig>
PATINA_INLINE vfloat<N> azimuth(const Vec3<vfloat<N>>& w) {
    using F = vfloat<N>;
    const F phi = Trig::atan2(w.y, w.x);
    return select(phi < F(0.0f), phi + F(kTwoPi), phi);
}

template <int N, class Trig>
PATINA_INLINE void anisotropic_coords(const Vec3<vfloat<N>>& wi, const Vec3<vfloat<N>>& wo, uint32_t symmetry,
                                      vfloat<N>* coord) {
    using F = vfloat<N>;
    F ti = acos_clamped<N, Trig>(wi.z), to = acos_clamped<N, Trig>(wo.z);
    F pi = azimuth<N, Trig>(wi), po = azimuth<N, Trig>(wo);
    if (symmetry & kSymReciprocity) {
        const vbool<N> swap = ti > to;
        const F t = select(swap, to, ti), p = select(swap, po, pi);
        to = select(swap, ti, to);
        po = select(swap, pi, po);
        ti = t;
        pi = p;
    }
    coord[0] = ti;
    coord[1] = pi;
    coord[2] = to;
    coord[3] = po;
}

template <int N, Parametrization P, class Trig>
PATINA_INLINE void coords(const Vec3<vfloat<N>>& wi, const Vec3<vfloat<N>>& wo, uint32_t symmetry, vfloat<N>* coord) {
    if constexpr (P == Parametrization::HalfDiff) halfdiff_coords<N, Trig>(wi, wo, symmetry, coord);
    else if constexpr (P == Parametrization::Isotropic) isotropic_coords<N, Trig>(wi, wo, symmetry, coord);
    else anisotropic_coords<N, Trig>(wi, wo, symmetry, coord);
}

constexpr int dims_of(Parametrization p) { return p == Parametrization::Anisotropic ? 4 : 3; }
}  // namespace eval_detail

namespace eval_detail {
// Pairs go through the evaluator a chunk at a time, in three passes (angles, cells,
// interpolation). Each pass is a loop of independent blocks of N pairs, which the CPU
// overlaps far better than one long dependent chain per block: the branchy search no
// longer stalls the arithmetic and the gathers of the blocks around it.
constexpr int kChunkPairs = 64;

template <int D>
struct Chunk {
    alignas(32) float coord[D][kChunkPairs];
    alignas(32) float frac[D][kChunkPairs];
    alignas(32) float above[kChunkPairs];  // 1 where both directions are above the horizon
    alignas(32) int32_t base[kChunkPairs];  // grid point of each pair's lower cell corner
};

// Pass 1: N pairs (rows of wi, wo) to the table's angles.
template <int N, Parametrization P, class Trig, int D>
PATINA_INLINE void block_angles(const TableView& t, const float* wi, const float* wo, Chunk<D>& c, int at) {
    using F = vfloat<N>;
    const Vec3<vfloat<N>> i = load_dirs<N>(wi), o = load_dirs<N>(wo);
    store_n<N>(c.above + at, select((i.z > F(0.0f)) & (o.z > F(0.0f)), F(1.0f), F(0.0f)));
    F coord[D];
    coords<N, P, Trig>(i, o, t.symmetry, coord);
    for (int a = 0; a < D; ++a) store_n<N>(c.coord[a] + at, coord[a]);
}

// Pass 2: per axis the coherent search, then the fraction within the cell.
template <int N, int D>
PATINA_INLINE void block_cells(const TableView& t, Chunk<D>& c, int at, SearchHint* hints) {
    using F = vfloat<N>;
    using I = vint<N>;
    const vbool<N> above = load_n<N>(c.above + at) > F(0.5f);
    I base(0);
    for (int a = 0; a < D; ++a) {
        const F x = load_n<N>(c.coord[a] + at);
        const Cells<N> cells = coherent_search_cells<N>(t.knots[a], t.lengths[a], x, above, hints[a]);
        const F knot = lookup_cells<N>(t.knots[a], t.lengths[a], cells, above);
        const F inv_width = lookup_cells<N>(t.inv_widths[a], t.lengths[a] - 1, cells, above);
        store_n<N>(c.frac[a] + at, clamp((x - knot) * inv_width, F(0.0f), F(1.0f)));
        base += cells.cell * I(t.strides[a]);
    }
    store_n<N>(c.base + at, base);
}

// Pass 3: multilinear interpolation of the 2^D corners; writes `lanes` rows of out.
template <int N, int D>
PATINA_INLINE void block_interpolate(const TableView& t, const Chunk<D>& c, int at, float* out, int lanes) {
    using F = vfloat<N>;
    using I = vint<N>;
    constexpr int kCorners = 1 << D;
    F frac[D];
    for (int a = 0; a < D; ++a) frac[a] = load_n<N>(c.frac[a] + at);
    const I base = load_n<N>(c.base + at);
    const F above = load_n<N>(c.above + at);

    F weight[kCorners];
    int32_t offset[kCorners];
    for (int k = 0; k < kCorners; ++k) {
        F w(1.0f);
        int32_t off = 0;
        for (int a = 0; a < D; ++a) {
            const bool upper = (k >> (D - 1 - a)) & 1;
            w = w * (upper ? frac[a] : F(1.0f) - frac[a]);
            off += upper ? t.strides[a] : 0;
        }
        weight[k] = w;
        offset[k] = off;
    }
    F norm = above;
    if (t.coverage) {
        F covered(0.0f);
        for (int k = 0; k < kCorners; ++k) {
            weight[k] = weight[k] * gather(t.coverage, base + I(offset[k]));
            covered += weight[k];
        }
        norm = select((above > F(0.5f)) & (covered > F(0.0f)), F(1.0f) / covered, F(0.0f));
    }

    const int C = t.channels;
    const I row = base * I(C);  // index of each pair's lower corner's first channel
    if (C == 3) {
        // the common RGB case: each corner's three channels in one load per lane, the sums
        // written as rows (core/simd/weighted_rows.h)
        int32_t row_offset[kCorners];
        for (int k = 0; k < kCorners; ++k) row_offset[k] = offset[k] * C;
        weighted_rows3<N, kCorners>(t.values, row, row_offset, weight, norm, out, lanes);
        return;
    }
    I corner[kCorners];  // index of each corner's first channel
    for (int k = 0; k < kCorners; ++k) corner[k] = row + I(offset[k] * C);
    for (int ch = 0; ch < C; ++ch) {
        const float* channel = t.values + ch;
        F acc(0.0f);
        for (int k = 0; k < kCorners; ++k) acc = madd(weight[k], gather(channel, corner[k]), acc);
        acc = acc * norm;
        if constexpr (N == 1) {
            out[ch] = acc;
        } else {
            alignas(32) float lane_values[N];
            acc.store(lane_values);
            for (int j = 0; j < lanes; ++j) out[j * C + ch] = lane_values[j];
        }
    }
}
}  // namespace eval_detail

// Evaluates pairs [begin, end) of (n, 3) arrays wi, wo into out (n, channels); any length.
// The tail goes through the same width-N code, padded with normal-incidence pairs.
template <int N, Parametrization P, class Trig>
inline void eval_range(const TableView& t, const float* wi, const float* wo, float* out, size_t begin, size_t end) {
    using namespace eval_detail;
    constexpr int D = dims_of(P);
    static_assert(kChunkPairs % N == 0, "chunks hold whole blocks");
    const int C = t.channels;
    Chunk<D> chunk;
    SearchHint hints[D];
    for (size_t first = begin; first < end; first += kChunkPairs) {
        const int count = static_cast<int>(std::min<size_t>(kChunkPairs, end - first));
        const int whole = count / N * N;
        const int blocks = (count + N - 1) / N * N;
        const float* ci = wi + 3 * first;
        const float* co = wo + 3 * first;
        for (int at = 0; at < whole; at += N) block_angles<N, P, Trig, D>(t, ci + 3 * at, co + 3 * at, chunk, at);
        if (whole < count) {
            float pad_i[3 * N], pad_o[3 * N];
            for (int j = 0; j < N; ++j) {
                pad_i[3 * j] = pad_i[3 * j + 1] = pad_o[3 * j] = pad_o[3 * j + 1] = 0.0f;
                pad_i[3 * j + 2] = pad_o[3 * j + 2] = 1.0f;
            }
            for (int j = 0; j < 3 * (count - whole); ++j) {
                pad_i[j] = ci[3 * whole + j];
                pad_o[j] = co[3 * whole + j];
            }
            block_angles<N, P, Trig, D>(t, pad_i, pad_o, chunk, whole);
        }
        for (int at = 0; at < blocks; at += N) block_cells<N, D>(t, chunk, at, hints);
        for (int at = 0; at < blocks; at += N)
            block_interpolate<N, D>(t, chunk, at, out + (first + at) * C, std::min(N, count - at));
    }
}

template <int N, class Trig = FastTrig>
inline void eval_range(const TableView& t, const float* wi, const float* wo, float* out, size_t begin, size_t end) {
    switch (t.parametrization) {
        case Parametrization::Isotropic:
            eval_range<N, Parametrization::Isotropic, Trig>(t, wi, wo, out, begin, end);
            break;
        case Parametrization::Anisotropic:
            eval_range<N, Parametrization::Anisotropic, Trig>(t, wi, wo, out, begin, end);
            break;
        case Parametrization::HalfDiff:
            eval_range<N, Parametrization::HalfDiff, Trig>(t, wi, wo, out, begin, end);
            break;
    }
}

PATINA_END_TARGET
