// Width 4: SSE4.1. Compiled only into translation units built with -msse4.1 or more.
#pragma once

#include <smmintrin.h>

#include <cstdint>

#include "vec1.h"

PATINA_BEGIN_TARGET

struct vbool4 {
    __m128 m;
    vbool4() = default;
    explicit vbool4(__m128 v) : m(v) {}
    vbool4(bool b) : m(_mm_castsi128_ps(_mm_set1_epi32(b ? -1 : 0))) {}
};
struct vint4 {
    __m128i v;
    vint4() = default;
    explicit vint4(__m128i x) : v(x) {}
    vint4(int32_t x) : v(_mm_set1_epi32(x)) {}
    static vint4 load(const int32_t* p) { return vint4(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p))); }
    void store(int32_t* p) const { _mm_storeu_si128(reinterpret_cast<__m128i*>(p), v); }
    int32_t operator[](int i) const {
        alignas(16) int32_t t[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(t), v);
        return t[i];
    }
};
struct vfloat4 {
    __m128 v;
    vfloat4() = default;
    explicit vfloat4(__m128 x) : v(x) {}
    vfloat4(float x) : v(_mm_set1_ps(x)) {}
    static vfloat4 load(const float* p) { return vfloat4(_mm_loadu_ps(p)); }
    void store(float* p) const { _mm_storeu_ps(p, v); }
    float operator[](int i) const {
        alignas(16) float t[4];
        _mm_store_ps(t, v);
        return t[i];
    }
};

// --- masks
PATINA_INLINE vbool4 operator&(vbool4 a, vbool4 b) { return vbool4(_mm_and_ps(a.m, b.m)); }
PATINA_INLINE vbool4 operator|(vbool4 a, vbool4 b) { return vbool4(_mm_or_ps(a.m, b.m)); }
PATINA_INLINE vbool4 operator^(vbool4 a, vbool4 b) { return vbool4(_mm_xor_ps(a.m, b.m)); }
PATINA_INLINE vbool4 operator!(vbool4 a) { return vbool4(_mm_xor_ps(a.m, _mm_castsi128_ps(_mm_set1_epi32(-1)))); }
PATINA_INLINE vbool4 andnot(vbool4 a, vbool4 b) { return vbool4(_mm_andnot_ps(a.m, b.m)); }
PATINA_INLINE int movemask(vbool4 a) { return _mm_movemask_ps(a.m); }
PATINA_INLINE bool any(vbool4 a) { return movemask(a) != 0; }
PATINA_INLINE bool all(vbool4 a) { return movemask(a) == 0xF; }
PATINA_INLINE bool none(vbool4 a) { return movemask(a) == 0; }
PATINA_INLINE bool lane(vbool4 a, int i) { return (movemask(a) >> i) & 1; }

// --- float arithmetic
PATINA_INLINE vfloat4 operator+(vfloat4 a, vfloat4 b) { return vfloat4(_mm_add_ps(a.v, b.v)); }
PATINA_INLINE vfloat4 operator-(vfloat4 a, vfloat4 b) { return vfloat4(_mm_sub_ps(a.v, b.v)); }
PATINA_INLINE vfloat4 operator*(vfloat4 a, vfloat4 b) { return vfloat4(_mm_mul_ps(a.v, b.v)); }
PATINA_INLINE vfloat4 operator/(vfloat4 a, vfloat4 b) { return vfloat4(_mm_div_ps(a.v, b.v)); }
PATINA_INLINE vfloat4 operator-(vfloat4 a) { return vfloat4(_mm_xor_ps(a.v, _mm_set1_ps(-0.0f))); }
PATINA_INLINE vfloat4& operator+=(vfloat4& a, vfloat4 b) { return a = a + b; }
PATINA_INLINE vfloat4& operator-=(vfloat4& a, vfloat4 b) { return a = a - b; }
PATINA_INLINE vfloat4& operator*=(vfloat4& a, vfloat4 b) { return a = a * b; }
// madd rounds twice at every width (bit-identical results); fmadd is fused where the
// hardware has FMA (width 8) and falls back to madd here: SSE4.1 has no FMA.
PATINA_INLINE vfloat4 madd(vfloat4 a, vfloat4 b, vfloat4 c) { return a * b + c; }
PATINA_INLINE vfloat4 nmadd(vfloat4 a, vfloat4 b, vfloat4 c) { return c - a * b; }
PATINA_INLINE vfloat4 fmadd(vfloat4 a, vfloat4 b, vfloat4 c) { return a * b + c; }
PATINA_INLINE vfloat4 min(vfloat4 a, vfloat4 b) { return vfloat4(_mm_min_ps(a.v, b.v)); }
PATINA_INLINE vfloat4 max(vfloat4 a, vfloat4 b) { return vfloat4(_mm_max_ps(a.v, b.v)); }
PATINA_INLINE vfloat4 clamp(vfloat4 x, vfloat4 lo, vfloat4 hi) { return min(max(x, lo), hi); }
PATINA_INLINE vfloat4 abs(vfloat4 a) { return vfloat4(_mm_andnot_ps(_mm_set1_ps(-0.0f), a.v)); }
PATINA_INLINE vfloat4 floor(vfloat4 a) { return vfloat4(_mm_floor_ps(a.v)); }
PATINA_INLINE vfloat4 sqrt_exact(vfloat4 a) { return vfloat4(_mm_sqrt_ps(a.v)); }
PATINA_INLINE vfloat4 rcp_estimate(vfloat4 a) { return vfloat4(_mm_rcp_ps(a.v)); }
PATINA_INLINE vfloat4 rsqrt_estimate(vfloat4 a) { return vfloat4(_mm_rsqrt_ps(a.v)); }
PATINA_INLINE vfloat4 copysign(vfloat4 mag, vfloat4 sgn) {
    const __m128 s = _mm_set1_ps(-0.0f);
    return vfloat4(_mm_or_ps(_mm_andnot_ps(s, mag.v), _mm_and_ps(s, sgn.v)));
}
PATINA_INLINE vfloat4 xorsign(vfloat4 a, vfloat4 sgn) {
    return vfloat4(_mm_xor_ps(a.v, _mm_and_ps(_mm_set1_ps(-0.0f), sgn.v)));
}
PATINA_INLINE vbool4 signbit(vfloat4 a) { return vbool4(_mm_castsi128_ps(_mm_srai_epi32(_mm_castps_si128(a.v), 31))); }

PATINA_INLINE vbool4 operator<(vfloat4 a, vfloat4 b) { return vbool4(_mm_cmplt_ps(a.v, b.v)); }
PATINA_INLINE vbool4 operator<=(vfloat4 a, vfloat4 b) { return vbool4(_mm_cmple_ps(a.v, b.v)); }
PATINA_INLINE vbool4 operator>(vfloat4 a, vfloat4 b) { return vbool4(_mm_cmpgt_ps(a.v, b.v)); }
PATINA_INLINE vbool4 operator>=(vfloat4 a, vfloat4 b) { return vbool4(_mm_cmpge_ps(a.v, b.v)); }
PATINA_INLINE vbool4 operator==(vfloat4 a, vfloat4 b) { return vbool4(_mm_cmpeq_ps(a.v, b.v)); }
PATINA_INLINE vbool4 operator!=(vfloat4 a, vfloat4 b) { return vbool4(_mm_cmpneq_ps(a.v, b.v)); }
PATINA_INLINE vbool4 isnan(vfloat4 a) { return vbool4(_mm_cmpunord_ps(a.v, a.v)); }

PATINA_INLINE vfloat4 select(vbool4 m, vfloat4 a, vfloat4 b) { return vfloat4(_mm_blendv_ps(b.v, a.v, m.m)); }
PATINA_INLINE vint4 select(vbool4 m, vint4 a, vint4 b) {
    return vint4(_mm_castps_si128(_mm_blendv_ps(_mm_castsi128_ps(b.v), _mm_castsi128_ps(a.v), m.m)));
}
PATINA_INLINE vbool4 select(vbool4 m, vbool4 a, vbool4 b) { return vbool4(_mm_blendv_ps(b.m, a.m, m.m)); }

// --- int arithmetic
PATINA_INLINE vint4 operator+(vint4 a, vint4 b) { return vint4(_mm_add_epi32(a.v, b.v)); }
PATINA_INLINE vint4 operator-(vint4 a, vint4 b) { return vint4(_mm_sub_epi32(a.v, b.v)); }
PATINA_INLINE vint4 operator*(vint4 a, vint4 b) { return vint4(_mm_mullo_epi32(a.v, b.v)); }
PATINA_INLINE vint4 operator&(vint4 a, vint4 b) { return vint4(_mm_and_si128(a.v, b.v)); }
PATINA_INLINE vint4 operator|(vint4 a, vint4 b) { return vint4(_mm_or_si128(a.v, b.v)); }
PATINA_INLINE vint4 operator<<(vint4 a, int s) { return vint4(_mm_slli_epi32(a.v, s)); }
PATINA_INLINE vint4 operator^(vint4 a, vint4 b) { return vint4(_mm_xor_si128(a.v, b.v)); }
PATINA_INLINE vint4 srl(vint4 a, int s) { return vint4(_mm_srli_epi32(a.v, s)); }
PATINA_INLINE vint4 mul_wrap(vint4 a, vint4 b) { return vint4(_mm_mullo_epi32(a.v, b.v)); }
PATINA_INLINE vint4 operator>>(vint4 a, int s) { return vint4(_mm_srai_epi32(a.v, s)); }
PATINA_INLINE vint4& operator+=(vint4& a, vint4 b) { return a = a + b; }
PATINA_INLINE vint4 min(vint4 a, vint4 b) { return vint4(_mm_min_epi32(a.v, b.v)); }
PATINA_INLINE vint4 max(vint4 a, vint4 b) { return vint4(_mm_max_epi32(a.v, b.v)); }
PATINA_INLINE vbool4 operator==(vint4 a, vint4 b) { return vbool4(_mm_castsi128_ps(_mm_cmpeq_epi32(a.v, b.v))); }
PATINA_INLINE vbool4 operator<(vint4 a, vint4 b) { return vbool4(_mm_castsi128_ps(_mm_cmplt_epi32(a.v, b.v))); }
PATINA_INLINE vbool4 operator>(vint4 a, vint4 b) { return vbool4(_mm_castsi128_ps(_mm_cmpgt_epi32(a.v, b.v))); }

PATINA_INLINE vint4 to_int_trunc(vfloat4 a) { return vint4(_mm_cvttps_epi32(a.v)); }
PATINA_INLINE vint4 as_int(vfloat4 a) { return vint4(_mm_castps_si128(a.v)); }
PATINA_INLINE vfloat4 as_float(vint4 a) { return vfloat4(_mm_castsi128_ps(a.v)); }
PATINA_INLINE vfloat4 to_float(vint4 a) { return vfloat4(_mm_cvtepi32_ps(a.v)); }

PATINA_INLINE float lane(vfloat4 v, int i) { return v[i]; }
PATINA_INLINE int32_t lane(vint4 v, int i) { return v[i]; }

// Four rows x y z (12 floats) to x, y, z vectors and back: three loads and five shuffles
// instead of twelve scalar loads.
PATINA_INLINE void load_xyz(const float* p, vfloat4& x, vfloat4& y, vfloat4& z) {
    const __m128 m0 = _mm_loadu_ps(p), m1 = _mm_loadu_ps(p + 4), m2 = _mm_loadu_ps(p + 8);
    const __m128 xy = _mm_shuffle_ps(m1, m2, _MM_SHUFFLE(2, 1, 3, 2));  // x2 y2 x3 y3
    const __m128 yz = _mm_shuffle_ps(m0, m1, _MM_SHUFFLE(1, 0, 2, 1));  // y0 z0 y1 z1
    x = vfloat4(_mm_shuffle_ps(m0, xy, _MM_SHUFFLE(2, 0, 3, 0)));
    y = vfloat4(_mm_shuffle_ps(yz, xy, _MM_SHUFFLE(3, 1, 2, 0)));
    z = vfloat4(_mm_shuffle_ps(yz, m2, _MM_SHUFFLE(3, 0, 3, 1)));
}
PATINA_INLINE void xyz_rows(vfloat4 x, vfloat4 y, vfloat4 z, __m128& m0, __m128& m1, __m128& m2) {
    const __m128 rxy = _mm_shuffle_ps(x.v, y.v, _MM_SHUFFLE(2, 0, 2, 0));  // x0 x2 y0 y2
    const __m128 ryz = _mm_shuffle_ps(y.v, z.v, _MM_SHUFFLE(3, 1, 3, 1));  // y1 y3 z1 z3
    const __m128 rzx = _mm_shuffle_ps(z.v, x.v, _MM_SHUFFLE(3, 1, 2, 0));  // z0 z2 x1 x3
    m0 = _mm_shuffle_ps(rxy, rzx, _MM_SHUFFLE(2, 0, 2, 0));               // x0 y0 z0 x1
    m1 = _mm_shuffle_ps(ryz, rxy, _MM_SHUFFLE(3, 1, 2, 0));               // y1 z1 x2 y2
    m2 = _mm_shuffle_ps(rzx, ryz, _MM_SHUFFLE(3, 1, 3, 1));               // z2 x3 y3 z3
}
PATINA_INLINE void store_xyz(float* p, vfloat4 x, vfloat4 y, vfloat4 z) {
    __m128 m0, m1, m2;
    xyz_rows(x, y, z, m0, m1, m2);
    _mm_storeu_ps(p, m0);
    _mm_storeu_ps(p + 4, m1);
    _mm_storeu_ps(p + 8, m2);
}

// Three consecutive floats at base[idx] for each lane: one 4-float load per lane and a
// 4x4 transpose instead of three 4-lane gathers. Reads one float past each row, so the
// array needs one float of padding after its end.
PATINA_INLINE void gather3(const float* base, vint4 idx, vfloat4& a, vfloat4& b, vfloat4& c) {
    const __m128 r0 = _mm_loadu_ps(base + _mm_cvtsi128_si32(idx.v));
    const __m128 r1 = _mm_loadu_ps(base + _mm_extract_epi32(idx.v, 1));
    const __m128 r2 = _mm_loadu_ps(base + _mm_extract_epi32(idx.v, 2));
    const __m128 r3 = _mm_loadu_ps(base + _mm_extract_epi32(idx.v, 3));
    const __m128 t0 = _mm_unpacklo_ps(r0, r1), t1 = _mm_unpacklo_ps(r2, r3);  // a0 a1 b0 b1, a2 a3 b2 b3
    const __m128 t2 = _mm_unpackhi_ps(r0, r1), t3 = _mm_unpackhi_ps(r2, r3);  // c0 c1 . ., c2 c3 . .
    a = vfloat4(_mm_movelh_ps(t0, t1));
    b = vfloat4(_mm_movehl_ps(t1, t0));
    c = vfloat4(_mm_movelh_ps(t2, t3));
}

// SSE4.1 has no gather: four scalar loads, which is what a 4-wide gather costs anyway.
PATINA_INLINE vfloat4 gather(const float* base, vint4 idx) {
    const int32_t i0 = _mm_cvtsi128_si32(idx.v), i1 = _mm_extract_epi32(idx.v, 1);
    const int32_t i2 = _mm_extract_epi32(idx.v, 2), i3 = _mm_extract_epi32(idx.v, 3);
    return vfloat4(_mm_setr_ps(base[i0], base[i1], base[i2], base[i3]));
}
PATINA_INLINE vint4 gather(const int32_t* base, vint4 idx) {
    const int32_t i0 = _mm_cvtsi128_si32(idx.v), i1 = _mm_extract_epi32(idx.v, 1);
    const int32_t i2 = _mm_extract_epi32(idx.v, 2), i3 = _mm_extract_epi32(idx.v, 3);
    return vint4(_mm_setr_epi32(base[i0], base[i1], base[i2], base[i3]));
}
// Inactive lanes read nothing and give 0.
PATINA_INLINE vfloat4 gather(const float* base, vint4 idx, vbool4 active) {
    return select(active, gather(base, select(active, idx, vint4(0))), vfloat4(0.0f));
}

PATINA_END_TARGET
