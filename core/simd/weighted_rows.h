// The weighted sum of K rows of three floats per lane, scaled, written out as N rows of three
// floats: the multilinear interpolation of an RGB table's cell corners (brdf/eval.h).
//
//   out[3j + c] = norm_j * (w[0]_j v[row_j + off[0] + c] + ... + w[K-1]_j v[row_j + off[K-1] + c])
//
// summed from k = 0 up, each term a product then a sum (madd), so every width gives width 1's
// bits. Reads one float past each row (4-float loads): the array needs one float of padding.
//
// Widths 1, 4 and 8 gather each corner's three channels into three vectors (gather3: a 4-float
// load a lane and a 4x4 transpose), sum them and interleave the result into rows (store_xyz).
// Width 16 does not transpose: each register holds four lanes' rows as loaded (r g b and one
// float ignored), the lanes' weights are spread to match (one vpermps per four lanes), and the
// sums come out as rows already (three vpermt2ps drop the ignored floats). On Zen 4, which runs
// 512-bit shuffles as two 256-bit halves, the transposes were the interpolation's cost: 25
// shuffles a corner (gather3 on both halves and the joins) against 4 here, the rows going in
// with masked broadcasts (load and blend, no shuffle). The four lanes of a register go through
// all K corners before the next four, so their row indices and the corners' base pointers stay
// in general registers (all sixteen lanes a corner at a time spilled them: 10.5 against 9
// cycles a pair).
#pragma once

#include <cstdint>

#include "core/simd/simd.h"

PATINA_BEGIN_TARGET

#if defined(PATINA_HAS_AVX512)
namespace weighted_rows_detail {
// Lane 4q + m / 4 of a vector into float m of the q-th group of four lanes: each lane's value
// beside its row.
PATINA_INLINE __m512 spread_quarter(__m512 v, int q) {
    const __m512i lane = _mm512_add_epi32(_mm512_set1_epi32(16 * q),
                                          _mm512_set_epi32(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0));
    return _mm512_permutexvar_ps(_mm512_srli_epi32(lane, 2), v);
}

// Index k < 32 of float k of out (row k / 3, channel k % 3) in two registers of four-float rows
// (float 4 (k / 3) + k % 3), for output register o reading rows registers o and o + 1.
PATINA_INLINE __m512i compact_index(int o) {
    alignas(64) int32_t idx[16];
    for (int j = 0; j < 16; ++j) {
        const int k = 16 * o + j;
        idx[j] = 4 * (k / 3) + k % 3 - 16 * o;
    }
    return _mm512_load_si512(idx);
}

template <int K>
PATINA_INLINE void weighted_rows3_w16(const float* values, vint16 row, const int32_t (&offset)[K],
                                      const vfloat16 (&weight)[K], vfloat16 norm, float* out, int lanes) {
    alignas(64) int32_t at[16];
    row.store(at);
    __m512 sum[4];
    for (int q = 0; q < 4; ++q) {
        // four lanes at a time: their four row indices and the K corners' bases stay in registers
        const int* a = at + 4 * q;
        sum[q] = _mm512_setzero_ps();
        for (int k = 0; k < K; ++k) {
            const float* v = values + offset[k];
            __m512 rows = _mm512_castps128_ps512(_mm_loadu_ps(v + a[0]));
            rows = _mm512_mask_broadcast_f32x4(rows, 0x00F0, _mm_loadu_ps(v + a[1]));
            rows = _mm512_mask_broadcast_f32x4(rows, 0x0F00, _mm_loadu_ps(v + a[2]));
            rows = _mm512_mask_broadcast_f32x4(rows, 0xF000, _mm_loadu_ps(v + a[3]));
            sum[q] = _mm512_add_ps(_mm512_mul_ps(spread_quarter(weight[k].v, q), rows), sum[q]);
        }
    }
    for (int q = 0; q < 4; ++q) sum[q] = _mm512_mul_ps(sum[q], spread_quarter(norm.v, q));
    alignas(64) float rows[48];
    float* dst = lanes == 16 ? out : rows;
    for (int o = 0; o < 3; ++o)
        _mm512_storeu_ps(dst + 16 * o, _mm512_permutex2var_ps(sum[o], compact_index(o), sum[o + 1]));
    if (lanes < 16)
        for (int j = 0; j < 3 * lanes; ++j) out[j] = rows[j];
}
}  // namespace weighted_rows_detail
#endif

// Writes `lanes` rows of out (all N but in a batch's last block). offset[k] is corner k's
// float offset from row (the same for every lane), weight[k] its weights. K is a constant, so
// the loops unroll and the weights stay in registers.
template <int N, int K>
PATINA_INLINE void weighted_rows3(const float* values, vint<N> row, const int32_t (&offset)[K],
                                  const vfloat<N> (&weight)[K], vfloat<N> norm, float* out, int lanes) {
#if defined(PATINA_HAS_AVX512)
    if constexpr (N == 16) {
        weighted_rows_detail::weighted_rows3_w16<K>(values, row, offset, weight, norm, out, lanes);
        return;
    }
#endif
    using F = vfloat<N>;
    vint<N> corner[K];  // all computed first, as GCC then keeps gather3's index extraction in memory
    for (int k = 0; k < K; ++k) corner[k] = row + vint<N>(offset[k]);
    F r(0.0f), g(0.0f), b(0.0f);
    for (int k = 0; k < K; ++k) {
        F cr, cg, cb;
        gather3(values, corner[k], cr, cg, cb);
        r = madd(weight[k], cr, r);
        g = madd(weight[k], cg, g);
        b = madd(weight[k], cb, b);
    }
    r = r * norm;
    g = g * norm;
    b = b * norm;
    if (N == 1 || lanes == N) {
        store_xyz(out, r, g, b);
    } else {
        alignas(32) float rows[3 * N];
        store_xyz(rows, r, g, b);
        for (int j = 0; j < 3 * lanes && j < 3 * N; ++j) out[j] = rows[j];
    }
}

PATINA_END_TARGET
