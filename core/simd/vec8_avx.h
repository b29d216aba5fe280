// Width 8: AVX2 + FMA. Compiled only into translation units built with
// -mavx2 -mfma; the run-time dispatcher (cpu.h) calls them only on CPUs that have both.
#pragma once

#include <immintrin.h>

#include <cstdint>

#include "vec4_sse.h"

PATINA_BEGIN_TARGET

struct vbool8 {
    __m256 m;
    vbool8() = default;
    explicit vbool8(__m256 v) : m(v) {}
    vbool8(bool b) : m(_mm256_castsi256_ps(_mm256_set1_epi32(b ? -1 : 0))) {}
};
struct vint8 {
    __m256i v;
    vint8() = default;
    explicit vint8(__m256i x) : v(x) {}
    vint8(int32_t x) : v(_mm256_set1_epi32(x)) {}
    static vint8 load(const int32_t* p) { return vint8(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p))); }
    void store(int32_t* p) const { _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), v); }
    int32_t operator[](int i) const {
        alignas(32) int32_t t[8];
        _mm256_store_si256(reinterpret_cast<__m256i*>(t), v);
        return t[i];
    }
};
struct vfloat8 {
    __m256 v;
    vfloat8() = default;
    explicit vfloat8(__m256 x) : v(x) {}
    vfloat8(float x) : v(_mm256_set1_ps(x)) {}
    static vfloat8 load(const float* p) { return vfloat8(_mm256_loadu_ps(p)); }
    void store(float* p) const { _mm256_storeu_ps(p, v); }
    float operator[](int i) const {
        alignas(32) float t[8];
        _mm256_store_ps(t, v);
        return t[i];
    }
};

// --- masks
PATINA_INLINE vbool8 operator&(vbool8 a, vbool8 b) { return vbool8(_mm256_and_ps(a.m, b.m)); }
PATINA_INLINE vbool8 operator|(vbool8 a, vbool8 b) { return vbool8(_mm256_or_ps(a.m, b.m)); }
PATINA_INLINE vbool8 operator^(vbool8 a, vbool8 b) { return vbool8(_mm256_xor_ps(a.m, b.m)); }
PATINA_INLINE vbool8 operator!(vbool8 a) {
    return vbool8(_mm256_xor_ps(a.m, _mm256_castsi256_ps(_mm256_set1_epi32(-1))));
}
PATINA_INLINE vbool8 andnot(vbool8 a, vbool8 b) { return vbool8(_mm256_andnot_ps(a.m, b.m)); }
PATINA_INLINE int movemask(vbool8 a) { return _mm256_movemask_ps(a.m); }
PATINA_INLINE bool any(vbool8 a) { return !_mm256_testz_ps(a.m, a.m); }
PATINA_INLINE bool all(vbool8 a) { return movemask(a) == 0xFF; }
PATINA_INLINE bool none(vbool8 a) { return _mm256_testz_ps(a.m, a.m); }
PATINA_INLINE bool lane(vbool8 a, int i) { return (movemask(a) >> i) & 1; }

// --- float arithmetic
PATINA_INLINE vfloat8 operator+(vfloat8 a, vfloat8 b) { return vfloat8(_mm256_add_ps(a.v, b.v)); }
PATINA_INLINE vfloat8 operator-(vfloat8 a, vfloat8 b) { return vfloat8(_mm256_sub_ps(a.v, b.v)); }
PATINA_INLINE vfloat8 operator*(vfloat8 a, vfloat8 b) { return vfloat8(_mm256_mul_ps(a.v, b.v)); }
PATINA_INLINE vfloat8 operator/(vfloat8 a, vfloat8 b) { return vfloat8(_mm256_div_ps(a.v, b.v)); }
PATINA_INLINE vfloat8 operator-(vfloat8 a) { return vfloat8(_mm256_xor_ps(a.v, _mm256_set1_ps(-0.0f))); }
PATINA_INLINE vfloat8& operator+=(vfloat8& a, vfloat8 b) { return a = a + b; }
PATINA_INLINE vfloat8& operator-=(vfloat8& a, vfloat8 b) { return a = a - b; }
PATINA_INLINE vfloat8& operator*=(vfloat8& a, vfloat8 b) { return a = a * b; }
// madd rounds twice, like widths 1 and 4, so every width gives bit-identical results
// (renders and fits do not depend on the CPU). fmadd is the FMA path, one rounding,
// for kernels that want the speed and accept last-bit differences between widths.
PATINA_INLINE vfloat8 madd(vfloat8 a, vfloat8 b, vfloat8 c) { return a * b + c; }
PATINA_INLINE vfloat8 nmadd(vfloat8 a, vfloat8 b, vfloat8 c) { return c - a * b; }
PATINA_INLINE vfloat8 fmadd(vfloat8 a, vfloat8 b, vfloat8 c) { return vfloat8(_mm256_fmadd_ps(a.v, b.v, c.v)); }
PATINA_INLINE vfloat8 min(vfloat8 a, vfloat8 b) { return vfloat8(_mm256_min_ps(a.v, b.v)); }
PATINA_INLINE vfloat8 max(vfloat8 a, vfloat8 b) { return vfloat8(_mm256_max_ps(a.v, b.v)); }
PATINA_INLINE vfloat8 clamp(vfloat8 x, vfloat8 lo, vfloat8 hi) { return min(max(x, lo), hi); }
PATINA_INLINE vfloat8 abs(vfloat8 a) { return vfloat8(_mm256_andnot_ps(_mm256_set1_ps(-0.0f), a.v)); }
PATINA_INLINE vfloat8 floor(vfloat8 a) { return vfloat8(_mm256_floor_ps(a.v)); }
PATINA_INLINE vfloat8 sqrt_exact(vfloat8 a) { return vfloat8(_mm256_sqrt_ps(a.v)); }
PATINA_INLINE vfloat8 rcp_estimate(vfloat8 a) { return vfloat8(_mm256_rcp_ps(a.v)); }
PATINA_INLINE vfloat8 rsqrt_estimate(vfloat8 a) { return vfloat8(_mm256_rsqrt_ps(a.v)); }
PATINA_INLINE vfloat8 copysign(vfloat8 mag, vfloat8 sgn) {
    const __m256 s = _mm256_set1_ps(-0.0f);
    return vfloat8(_mm256_or_ps(_mm256_andnot_ps(s, mag.v), _mm256_and_ps(s, sgn.v)));
}
PATINA_INLINE vfloat8 xorsign(vfloat8 a, vfloat8 sgn) {
    return vfloat8(_mm256_xor_ps(a.v, _mm256_and_ps(_mm256_set1_ps(-0.0f), sgn.v)));
}
PATINA_INLINE vbool8 signbit(vfloat8 a) {
    return vbool8(_mm256_castsi256_ps(_mm256_srai_epi32(_mm256_castps_si256(a.v), 31)));
}

PATINA_INLINE vbool8 operator<(vfloat8 a, vfloat8 b) { return vbool8(_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)); }
PATINA_INLINE vbool8 operator<=(vfloat8 a, vfloat8 b) { return vbool8(_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)); }
PATINA_INLINE vbool8 operator>(vfloat8 a, vfloat8 b) { return vbool8(_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)); }
PATINA_INLINE vbool8 operator>=(vfloat8 a, vfloat8 b) { return vbool8(_mm256_cmp_ps(a.v, b.v, _CMP_GE_OQ)); }
PATINA_INLINE vbool8 operator==(vfloat8 a, vfloat8 b) { return vbool8(_mm256_cmp_ps(a.v, b.v, _CMP_EQ_OQ)); }
PATINA_INLINE vbool8 operator!=(vfloat8 a, vfloat8 b) { return vbool8(_mm256_cmp_ps(a.v, b.v, _CMP_NEQ_UQ)); }
PATINA_INLINE vbool8 isnan(vfloat8 a) { return vbool8(_mm256_cmp_ps(a.v, a.v, _CMP_UNORD_Q)); }

PATINA_INLINE vfloat8 select(vbool8 m, vfloat8 a, vfloat8 b) { return vfloat8(_mm256_blendv_ps(b.v, a.v, m.m)); }
PATINA_INLINE vint8 select(vbool8 m, vint8 a, vint8 b) {
    return vint8(_mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(b.v), _mm256_castsi256_ps(a.v), m.m)));
}
PATINA_INLINE vbool8 select(vbool8 m, vbool8 a, vbool8 b) { return vbool8(_mm256_blendv_ps(b.m, a.m, m.m)); }

// --- int arithmetic
PATINA_INLINE vint8 operator+(vint8 a, vint8 b) { return vint8(_mm256_add_epi32(a.v, b.v)); }
PATINA_INLINE vint8 operator-(vint8 a, vint8 b) { return vint8(_mm256_sub_epi32(a.v, b.v)); }
PATINA_INLINE vint8 operator*(vint8 a, vint8 b) { return vint8(_mm256_mullo_epi32(a.v, b.v)); }
PATINA_INLINE vint8 operator&(vint8 a, vint8 b) { return vint8(_mm256_and_si256(a.v, b.v)); }
PATINA_INLINE vint8 operator|(vint8 a, vint8 b) { return vint8(_mm256_or_si256(a.v, b.v)); }
PATINA_INLINE vint8 operator<<(vint8 a, int s) { return vint8(_mm256_slli_epi32(a.v, s)); }
PATINA_INLINE vint8 operator^(vint8 a, vint8 b) { return vint8(_mm256_xor_si256(a.v, b.v)); }
PATINA_INLINE vint8 srl(vint8 a, int s) { return vint8(_mm256_srli_epi32(a.v, s)); }
PATINA_INLINE vint8 mul_wrap(vint8 a, vint8 b) { return vint8(_mm256_mullo_epi32(a.v, b.v)); }
PATINA_INLINE vint8 operator>>(vint8 a, int s) { return vint8(_mm256_srai_epi32(a.v, s)); }
PATINA_INLINE vint8& operator+=(vint8& a, vint8 b) { return a = a + b; }
PATINA_INLINE vint8 min(vint8 a, vint8 b) { return vint8(_mm256_min_epi32(a.v, b.v)); }
PATINA_INLINE vint8 max(vint8 a, vint8 b) { return vint8(_mm256_max_epi32(a.v, b.v)); }
PATINA_INLINE vbool8 operator==(vint8 a, vint8 b) { return vbool8(_mm256_castsi256_ps(_mm256_cmpeq_epi32(a.v, b.v))); }
PATINA_INLINE vbool8 operator>(vint8 a, vint8 b) { return vbool8(_mm256_castsi256_ps(_mm256_cmpgt_epi32(a.v, b.v))); }
PATINA_INLINE vbool8 operator<(vint8 a, vint8 b) { return b > a; }

PATINA_INLINE vint8 to_int_trunc(vfloat8 a) { return vint8(_mm256_cvttps_epi32(a.v)); }
PATINA_INLINE vint8 as_int(vfloat8 a) { return vint8(_mm256_castps_si256(a.v)); }
PATINA_INLINE vfloat8 as_float(vint8 a) { return vfloat8(_mm256_castsi256_ps(a.v)); }
PATINA_INLINE vfloat8 to_float(vint8 a) { return vfloat8(_mm256_cvtepi32_ps(a.v)); }

PATINA_INLINE float lane(vfloat8 v, int i) { return v[i]; }
PATINA_INLINE int32_t lane(vint8 v, int i) { return v[i]; }

// Eight rows x y z (24 floats) to x, y, z vectors and back: the 4-wide shuffles on both
// 128-bit halves (rows 0-3 low, 4-7 high).
PATINA_INLINE void load_xyz(const float* p, vfloat8& x, vfloat8& y, vfloat8& z) {
    const __m256 m03 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(p)), _mm_loadu_ps(p + 12), 1);
    const __m256 m14 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(p + 4)), _mm_loadu_ps(p + 16), 1);
    const __m256 m25 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(p + 8)), _mm_loadu_ps(p + 20), 1);
    const __m256 xy = _mm256_shuffle_ps(m14, m25, _MM_SHUFFLE(2, 1, 3, 2));
    const __m256 yz = _mm256_shuffle_ps(m03, m14, _MM_SHUFFLE(1, 0, 2, 1));
    x = vfloat8(_mm256_shuffle_ps(m03, xy, _MM_SHUFFLE(2, 0, 3, 0)));
    y = vfloat8(_mm256_shuffle_ps(yz, xy, _MM_SHUFFLE(3, 1, 2, 0)));
    z = vfloat8(_mm256_shuffle_ps(yz, m25, _MM_SHUFFLE(3, 0, 3, 1)));
}
PATINA_INLINE void store_xyz(float* p, vfloat8 x, vfloat8 y, vfloat8 z) {
    const __m256 rxy = _mm256_shuffle_ps(x.v, y.v, _MM_SHUFFLE(2, 0, 2, 0));
    const __m256 ryz = _mm256_shuffle_ps(y.v, z.v, _MM_SHUFFLE(3, 1, 3, 1));
    const __m256 rzx = _mm256_shuffle_ps(z.v, x.v, _MM_SHUFFLE(3, 1, 2, 0));
    const __m256 m03 = _mm256_shuffle_ps(rxy, rzx, _MM_SHUFFLE(2, 0, 2, 0));
    const __m256 m14 = _mm256_shuffle_ps(ryz, rxy, _MM_SHUFFLE(3, 1, 2, 0));
    const __m256 m25 = _mm256_shuffle_ps(rzx, ryz, _MM_SHUFFLE(3, 1, 3, 1));
    _mm256_storeu_ps(p, _mm256_permute2f128_ps(m03, m14, 0x20));       // floats 0-3 | 4-7
    _mm256_storeu_ps(p + 8, _mm256_permute2f128_ps(m25, m03, 0x30));   // floats 8-11 | 12-15
    _mm256_storeu_ps(p + 16, _mm256_permute2f128_ps(m14, m25, 0x31));  // floats 16-19 | 20-23
}

// Three consecutive floats at base[idx] for each lane: eight 4-float loads and a 4x4
// transpose in each 128-bit half, instead of three 8-lane gathers (24 loads). Reads one
// float past each row, so the array needs one float of padding after its end.
PATINA_INLINE void gather3(const float* base, vint8 idx, vfloat8& a, vfloat8& b, vfloat8& c) {
    alignas(32) int32_t i[8];
    idx.store(i);
    auto row = [&](int lo, int hi) {
        return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(base + i[lo])), _mm_loadu_ps(base + i[hi]), 1);
    };
    const __m256 r0 = row(0, 4), r1 = row(1, 5), r2 = row(2, 6), r3 = row(3, 7);
    const __m256 t0 = _mm256_unpacklo_ps(r0, r1), t1 = _mm256_unpacklo_ps(r2, r3);
    const __m256 t2 = _mm256_unpackhi_ps(r0, r1), t3 = _mm256_unpackhi_ps(r2, r3);
    a = vfloat8(_mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(1, 0, 1, 0)));
    b = vfloat8(_mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(3, 2, 3, 2)));
    c = vfloat8(_mm256_shuffle_ps(t2, t3, _MM_SHUFFLE(1, 0, 1, 0)));
}

PATINA_INLINE vfloat8 gather(const float* base, vint8 idx) { return vfloat8(_mm256_i32gather_ps(base, idx.v, 4)); }
PATINA_INLINE vint8 gather(const int32_t* base, vint8 idx) {
    return vint8(_mm256_i32gather_epi32(reinterpret_cast<const int*>(base), idx.v, 4));
}
// Inactive lanes read nothing and give 0.
PATINA_INLINE vfloat8 gather(const float* base, vint8 idx, vbool8 active) {
    return vfloat8(_mm256_mask_i32gather_ps(_mm256_setzero_ps(), base, idx.v, active.m, 4));
}

// A gather from a 16-float window held in two registers (lo: floats 0-7, hi: 8-15), each lane
// taking float idx & 15: two vpermps and a blend on bit 3, where a gather is one load a lane.
// The coherent search's in-register lookups (brdf/search.h).
PATINA_INLINE vfloat8 permute2(vfloat8 lo, vfloat8 hi, vint8 idx) {
    const __m256 a = _mm256_permutevar8x32_ps(lo.v, idx.v), b = _mm256_permutevar8x32_ps(hi.v, idx.v);
    return vfloat8(_mm256_blendv_ps(a, b, _mm256_castsi256_ps(_mm256_slli_epi32(idx.v, 28))));
}

PATINA_END_TARGET
