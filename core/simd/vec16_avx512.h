// Width 16: AVX-512 F + VL + DQ + BW, with FMA. Compiled only into translation units built
// with PATINA_AVX512_FLAGS (CMakeLists.txt); the run-time dispatcher (cpu.h) calls them only
// on CPUs whose CPUID reports all four subsets and whose OS saves the opmask and ZMM state
// (XGETBV). vbool16 is a mask register (__mmask16), not a vector of all-ones lanes.
//
// Every operation gives, lane by lane, the bits width 1 gives (and widths 4 and 8): the
// same IEEE operations and compare predicates, min/max with minps' NaN rule (the second
// operand), madd rounding twice (no contraction: -ffp-contract=off), and the reciprocal
// estimates from the same 12-bit tables as widths 4 and 8 (two 8-wide rcpps / rsqrtps, not
// AVX-512's rcp14, whose different bits would make fast_rcp differ from width 8).
#pragma once

#include <immintrin.h>

#include <cstdint>

#include "vec8_avx.h"

PATINA_BEGIN_TARGET

struct vbool16 {
    __mmask16 m;
    vbool16() = default;
    explicit vbool16(__mmask16 k) : m(k) {}
    vbool16(bool b) : m(static_cast<__mmask16>(b ? 0xFFFF : 0)) {}
};
struct vint16 {
    __m512i v;
    vint16() = default;
    explicit vint16(__m512i x) : v(x) {}
    vint16(int32_t x) : v(_mm512_set1_epi32(x)) {}
    static vint16 load(const int32_t* p) { return vint16(_mm512_loadu_si512(p)); }
    void store(int32_t* p) const { _mm512_storeu_si512(p, v); }
    int32_t operator[](int i) const {
        alignas(64) int32_t t[16];
        _mm512_store_si512(t, v);
        return t[i];
    }
};
struct vfloat16 {
    __m512 v;
    vfloat16() = default;
    explicit vfloat16(__m512 x) : v(x) {}
    vfloat16(float x) : v(_mm512_set1_ps(x)) {}
    static vfloat16 load(const float* p) { return vfloat16(_mm512_loadu_ps(p)); }
    void store(float* p) const { _mm512_storeu_ps(p, v); }
    float operator[](int i) const {
        alignas(64) float t[16];
        _mm512_store_ps(t, v);
        return t[i];
    }
};

// --- masks (k registers)
PATINA_INLINE vbool16 operator&(vbool16 a, vbool16 b) { return vbool16(_kand_mask16(a.m, b.m)); }
PATINA_INLINE vbool16 operator|(vbool16 a, vbool16 b) { return vbool16(_kor_mask16(a.m, b.m)); }
PATINA_INLINE vbool16 operator^(vbool16 a, vbool16 b) { return vbool16(_kxor_mask16(a.m, b.m)); }
PATINA_INLINE vbool16 operator!(vbool16 a) { return vbool16(_knot_mask16(a.m)); }
PATINA_INLINE vbool16 andnot(vbool16 a, vbool16 b) { return vbool16(_kandn_mask16(a.m, b.m)); }  // (!a) & b
PATINA_INLINE int movemask(vbool16 a) { return static_cast<int>(a.m); }
PATINA_INLINE bool any(vbool16 a) { return a.m != 0; }
PATINA_INLINE bool all(vbool16 a) { return a.m == 0xFFFF; }
PATINA_INLINE bool none(vbool16 a) { return a.m == 0; }
PATINA_INLINE bool lane(vbool16 a, int i) { return (a.m >> i) & 1; }

// --- float arithmetic
PATINA_INLINE vfloat16 operator+(vfloat16 a, vfloat16 b) { return vfloat16(_mm512_add_ps(a.v, b.v)); }
PATINA_INLINE vfloat16 operator-(vfloat16 a, vfloat16 b) { return vfloat16(_mm512_sub_ps(a.v, b.v)); }
PATINA_INLINE vfloat16 operator*(vfloat16 a, vfloat16 b) { return vfloat16(_mm512_mul_ps(a.v, b.v)); }
PATINA_INLINE vfloat16 operator/(vfloat16 a, vfloat16 b) { return vfloat16(_mm512_div_ps(a.v, b.v)); }
PATINA_INLINE vfloat16 operator-(vfloat16 a) { return vfloat16(_mm512_xor_ps(a.v, _mm512_set1_ps(-0.0f))); }
PATINA_INLINE vfloat16& operator+=(vfloat16& a, vfloat16 b) { return a = a + b; }
PATINA_INLINE vfloat16& operator-=(vfloat16& a, vfloat16 b) { return a = a - b; }
PATINA_INLINE vfloat16& operator*=(vfloat16& a, vfloat16 b) { return a = a * b; }
// madd rounds twice, as at every width (bit-identical results); fmadd is the one-rounding
// FMA, as at width 8 (see vec8_avx.h).
PATINA_INLINE vfloat16 madd(vfloat16 a, vfloat16 b, vfloat16 c) { return a * b + c; }
PATINA_INLINE vfloat16 nmadd(vfloat16 a, vfloat16 b, vfloat16 c) { return c - a * b; }
PATINA_INLINE vfloat16 fmadd(vfloat16 a, vfloat16 b, vfloat16 c) { return vfloat16(_mm512_fmadd_ps(a.v, b.v, c.v)); }
// vminps / vmaxps: when either is NaN (or both are zeros) the second operand, as at width 1.
PATINA_INLINE vfloat16 min(vfloat16 a, vfloat16 b) { return vfloat16(_mm512_min_ps(a.v, b.v)); }
PATINA_INLINE vfloat16 max(vfloat16 a, vfloat16 b) { return vfloat16(_mm512_max_ps(a.v, b.v)); }
PATINA_INLINE vfloat16 clamp(vfloat16 x, vfloat16 lo, vfloat16 hi) { return min(max(x, lo), hi); }
PATINA_INLINE vfloat16 abs(vfloat16 a) { return vfloat16(_mm512_andnot_ps(_mm512_set1_ps(-0.0f), a.v)); }
// vrndscaleps with scale 0 (imm bits 7:4) and rounding towards -inf; the immediate is one
// parenthesised constant, as some emulations of this intrinsic (SIMDe) are macros that shift it.
PATINA_INLINE vfloat16 floor(vfloat16 a) {
    constexpr int kFloor = (_MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    return vfloat16(_mm512_roundscale_ps(a.v, kFloor));
}
PATINA_INLINE vfloat16 sqrt_exact(vfloat16 a) { return vfloat16(_mm512_sqrt_ps(a.v)); }
namespace vec16_detail {
PATINA_INLINE __m256 lo(__m512 a) { return _mm512_castps512_ps256(a); }
PATINA_INLINE __m256 hi(__m512 a) { return _mm512_extractf32x8_ps(a, 1); }
PATINA_INLINE __m512 join(__m256 l, __m256 h) { return _mm512_insertf32x8(_mm512_castps256_ps512(l), h, 1); }
PATINA_INLINE __m256i lo(__m512i a) { return _mm512_castsi512_si256(a); }
PATINA_INLINE __m256i hi(__m512i a) { return _mm512_extracti32x8_epi32(a, 1); }
PATINA_INLINE __m512 join_ps(vfloat8 l, vfloat8 h) { return join(l.v, h.v); }
}  // namespace vec16_detail
// The 12-bit estimates of widths 4 and 8, on each half (see the top of this file).
PATINA_INLINE vfloat16 rcp_estimate(vfloat16 a) {
    using namespace vec16_detail;
    return vfloat16(join(_mm256_rcp_ps(lo(a.v)), _mm256_rcp_ps(hi(a.v))));
}
PATINA_INLINE vfloat16 rsqrt_estimate(vfloat16 a) {
    using namespace vec16_detail;
    return vfloat16(join(_mm256_rsqrt_ps(lo(a.v)), _mm256_rsqrt_ps(hi(a.v))));
}
PATINA_INLINE vfloat16 copysign(vfloat16 mag, vfloat16 sgn) {
    const __m512 s = _mm512_set1_ps(-0.0f);
    return vfloat16(_mm512_or_ps(_mm512_andnot_ps(s, mag.v), _mm512_and_ps(s, sgn.v)));
}
PATINA_INLINE vfloat16 xorsign(vfloat16 a, vfloat16 sgn) {
    return vfloat16(_mm512_xor_ps(a.v, _mm512_and_ps(_mm512_set1_ps(-0.0f), sgn.v)));
}
PATINA_INLINE vbool16 signbit(vfloat16 a) { return vbool16(_mm512_movepi32_mask(_mm512_castps_si512(a.v))); }

// The predicates of vec8_avx.h: ordered for < <= > >= ==, unordered for != (NaN != x).
PATINA_INLINE vbool16 operator<(vfloat16 a, vfloat16 b) { return vbool16(_mm512_cmp_ps_mask(a.v, b.v, _CMP_LT_OQ)); }
PATINA_INLINE vbool16 operator<=(vfloat16 a, vfloat16 b) { return vbool16(_mm512_cmp_ps_mask(a.v, b.v, _CMP_LE_OQ)); }
PATINA_INLINE vbool16 operator>(vfloat16 a, vfloat16 b) { return vbool16(_mm512_cmp_ps_mask(a.v, b.v, _CMP_GT_OQ)); }
PATINA_INLINE vbool16 operator>=(vfloat16 a, vfloat16 b) { return vbool16(_mm512_cmp_ps_mask(a.v, b.v, _CMP_GE_OQ)); }
PATINA_INLINE vbool16 operator==(vfloat16 a, vfloat16 b) { return vbool16(_mm512_cmp_ps_mask(a.v, b.v, _CMP_EQ_OQ)); }
PATINA_INLINE vbool16 operator!=(vfloat16 a, vfloat16 b) {
    return vbool16(_mm512_cmp_ps_mask(a.v, b.v, _CMP_NEQ_UQ));
}
PATINA_INLINE vbool16 isnan(vfloat16 a) { return vbool16(_mm512_cmp_ps_mask(a.v, a.v, _CMP_UNORD_Q)); }

// _mm512_mask_blend(k, x, y) takes y where k is set.
PATINA_INLINE vfloat16 select(vbool16 m, vfloat16 a, vfloat16 b) {
    return vfloat16(_mm512_mask_blend_ps(m.m, b.v, a.v));
}
PATINA_INLINE vint16 select(vbool16 m, vint16 a, vint16 b) { return vint16(_mm512_mask_blend_epi32(m.m, b.v, a.v)); }
PATINA_INLINE vbool16 select(vbool16 m, vbool16 a, vbool16 b) { return (m & a) | andnot(m, b); }

// --- int arithmetic
PATINA_INLINE vint16 operator+(vint16 a, vint16 b) { return vint16(_mm512_add_epi32(a.v, b.v)); }
PATINA_INLINE vint16 operator-(vint16 a, vint16 b) { return vint16(_mm512_sub_epi32(a.v, b.v)); }
PATINA_INLINE vint16 operator*(vint16 a, vint16 b) { return vint16(_mm512_mullo_epi32(a.v, b.v)); }
PATINA_INLINE vint16 operator&(vint16 a, vint16 b) { return vint16(_mm512_and_si512(a.v, b.v)); }
PATINA_INLINE vint16 operator|(vint16 a, vint16 b) { return vint16(_mm512_or_si512(a.v, b.v)); }
PATINA_INLINE vint16 operator^(vint16 a, vint16 b) { return vint16(_mm512_xor_si512(a.v, b.v)); }
// Shift counts as a vector operand (vpslld zmm, xmm): defined for any count at any -O level,
// where the immediate forms need a compile-time constant when not optimising.
PATINA_INLINE vint16 operator<<(vint16 a, int s) { return vint16(_mm512_sll_epi32(a.v, _mm_cvtsi32_si128(s))); }
PATINA_INLINE vint16 srl(vint16 a, int s) { return vint16(_mm512_srl_epi32(a.v, _mm_cvtsi32_si128(s))); }
PATINA_INLINE vint16 operator>>(vint16 a, int s) { return vint16(_mm512_sra_epi32(a.v, _mm_cvtsi32_si128(s))); }
PATINA_INLINE vint16 mul_wrap(vint16 a, vint16 b) { return vint16(_mm512_mullo_epi32(a.v, b.v)); }
PATINA_INLINE vint16& operator+=(vint16& a, vint16 b) { return a = a + b; }
PATINA_INLINE vint16 min(vint16 a, vint16 b) { return vint16(_mm512_min_epi32(a.v, b.v)); }
PATINA_INLINE vint16 max(vint16 a, vint16 b) { return vint16(_mm512_max_epi32(a.v, b.v)); }
PATINA_INLINE vbool16 operator==(vint16 a, vint16 b) { return vbool16(_mm512_cmpeq_epi32_mask(a.v, b.v)); }
PATINA_INLINE vbool16 operator>(vint16 a, vint16 b) { return vbool16(_mm512_cmpgt_epi32_mask(a.v, b.v)); }
PATINA_INLINE vbool16 operator<(vint16 a, vint16 b) { return b > a; }

// vcvttps2dq: NaN and out-of-range give INT32_MIN, as cvttps2dq at widths 4 and 8.
PATINA_INLINE vint16 to_int_trunc(vfloat16 a) { return vint16(_mm512_cvttps_epi32(a.v)); }
PATINA_INLINE vint16 as_int(vfloat16 a) { return vint16(_mm512_castps_si512(a.v)); }
PATINA_INLINE vfloat16 as_float(vint16 a) { return vfloat16(_mm512_castsi512_ps(a.v)); }
PATINA_INLINE vfloat16 to_float(vint16 a) { return vfloat16(_mm512_cvtepi32_ps(a.v)); }

PATINA_INLINE float lane(vfloat16 v, int i) { return v[i]; }
PATINA_INLINE int32_t lane(vint16 v, int i) { return v[i]; }

namespace vec16_detail {
// Index vectors for _mm512_permutex2var_ps over two registers (index k < 16: first, k - 16:
// second), built from the rule they implement so the tables cannot disagree with it.
struct XyzIndex {
    alignas(64) int32_t first[3][16];   // load: component c of rows 0..15 from floats 0..31
    alignas(64) int32_t second[3][16];  // load: ... completed from floats 32..47
    alignas(64) int32_t out_xy[3][16];  // store: floats 16o..16o+15 taken from x and y
    alignas(64) int32_t out_z[3][16];   // store: ... completed from z
    constexpr XyzIndex() : first(), second(), out_xy(), out_z() {
        for (int c = 0; c < 3; ++c)
            for (int j = 0; j < 16; ++j) {
                const int k = 3 * j + c;  // the float of row j, component c, in the 48
                first[c][j] = k < 32 ? k : 0;
                second[c][j] = k < 32 ? j : 16 + (k - 32);
            }
        for (int o = 0; o < 3; ++o)
            for (int j = 0; j < 16; ++j) {
                const int i = 16 * o + j, row = i / 3, comp = i % 3;
                out_xy[o][j] = comp == 0 ? row : comp == 1 ? 16 + row : 0;
                out_z[o][j] = comp == 2 ? 16 + row : j;
            }
    }
};
inline constexpr XyzIndex kXyz{};
PATINA_INLINE __m512i idx(const int32_t* t) { return _mm512_load_si512(t); }
}  // namespace vec16_detail

// Sixteen rows x y z (48 floats) to x, y, z vectors and back: three loads and six two-source
// permutes each way.
PATINA_INLINE void load_xyz(const float* p, vfloat16& x, vfloat16& y, vfloat16& z) {
    using namespace vec16_detail;
    const __m512 m0 = _mm512_loadu_ps(p), m1 = _mm512_loadu_ps(p + 16), m2 = _mm512_loadu_ps(p + 32);
    vfloat16* out[3] = {&x, &y, &z};
    for (int c = 0; c < 3; ++c) {
        const __m512 t = _mm512_permutex2var_ps(m0, idx(kXyz.first[c]), m1);
        out[c]->v = _mm512_permutex2var_ps(t, idx(kXyz.second[c]), m2);
    }
}
PATINA_INLINE void store_xyz(float* p, vfloat16 x, vfloat16 y, vfloat16 z) {
    using namespace vec16_detail;
    for (int o = 0; o < 3; ++o) {
        const __m512 t = _mm512_permutex2var_ps(x.v, idx(kXyz.out_xy[o]), y.v);
        _mm512_storeu_ps(p + 16 * o, _mm512_permutex2var_ps(t, idx(kXyz.out_z[o]), z.v));
    }
}

// Three consecutive floats at base[idx] for each lane: the 8-wide gather3 on each half (one
// 4-float load per lane and 4x4 transposes), so it reads, like it, one float past each row:
// the array needs one float of padding after its end.
PATINA_INLINE void gather3(const float* base, vint16 idx, vfloat16& a, vfloat16& b, vfloat16& c) {
    using namespace vec16_detail;
    vfloat8 a0, b0, c0, a1, b1, c1;
    gather3(base, vint8(lo(idx.v)), a0, b0, c0);
    gather3(base, vint8(hi(idx.v)), a1, b1, c1);
    a = vfloat16(join_ps(a0, a1));
    b = vfloat16(join_ps(b0, b1));
    c = vfloat16(join_ps(c0, c1));
}

PATINA_INLINE vfloat16 gather(const float* base, vint16 idx) { return vfloat16(_mm512_i32gather_ps(idx.v, base, 4)); }
PATINA_INLINE vint16 gather(const int32_t* base, vint16 idx) {
    return vint16(_mm512_i32gather_epi32(idx.v, base, 4));
}
// Inactive lanes read nothing (a masked-off gather lane does not touch memory) and give 0.
PATINA_INLINE vfloat16 gather(const float* base, vint16 idx, vbool16 active) {
    return vfloat16(_mm512_mask_i32gather_ps(_mm512_setzero_ps(), active.m, idx.v, base, 4));
}

// A gather from a 32-float window held in two registers (lo: floats 0-15, hi: 16-31), each lane
// taking float idx & 31: one vpermt2ps, where a gather is one load a lane (brdf/search.h).
PATINA_INLINE vfloat16 permute2(vfloat16 lo, vfloat16 hi, vint16 idx) {
    return vfloat16(_mm512_permutex2var_ps(lo.v, idx.v, hi.v));
}

PATINA_END_TARGET
