// Patina's SIMD vocabulary: vfloat<N>, vint<N>, vbool<N> for N = 1, 4, 8, 16.
//
// N = 1 is plain float / int32_t / bool; N = 4 is SSE4.1 (available when the
// translation unit is compiled with -msse4.1); N = 8 is AVX2 + FMA (only in
// translation units compiled with -mavx2 -mfma); N = 16 is AVX-512 F/VL/DQ/BW (only in
// translation units compiled with PATINA_AVX512_FLAGS, CMakeLists.txt). Kernels are written once as
// `template <int N>` using free functions (select, any, madd, gather, ...).
#pragma once

#include "target.h"
#include "vec1.h"
#if defined(PATINA_HAS_SSE4)
#include "vec4_sse.h"
#endif
#if defined(PATINA_HAS_AVX2)
#include "vec8_avx.h"
#endif
#if defined(PATINA_HAS_AVX512)
#include "vec16_avx512.h"
#endif

PATINA_BEGIN_TARGET

template <int N>
struct Simd;
template <>
struct Simd<1> {
    using F = float;
    using I = int32_t;
    using B = bool;
};
#if defined(PATINA_HAS_SSE4)
template <>
struct Simd<4> {
    using F = vfloat4;
    using I = vint4;
    using B = vbool4;
};
#endif
#if defined(PATINA_HAS_AVX2)
template <>
struct Simd<8> {
    using F = vfloat8;
    using I = vint8;
    using B = vbool8;
};
#endif
#if defined(PATINA_HAS_AVX512)
template <>
struct Simd<16> {
    using F = vfloat16;
    using I = vint16;
    using B = vbool16;
};
#endif

template <int N>
using vfloat = typename Simd<N>::F;
template <int N>
using vint = typename Simd<N>::I;
template <int N>
using vbool = typename Simd<N>::B;

// Mask and integer types that go with a float vector type, for code templated on the type.
template <class F>
using mask_t = decltype(F() < F());
template <class F>
using int_t = decltype(to_int_trunc(F()));

template <int N>
PATINA_INLINE vfloat<N> load_n(const float* p) {
    if constexpr (N == 1) return *p; else return vfloat<N>::load(p);
}
template <int N>
PATINA_INLINE vint<N> load_n(const int32_t* p) {
    if constexpr (N == 1) return *p; else return vint<N>::load(p);
}
template <int N>
PATINA_INLINE void store_n(float* p, vfloat<N> v) {
    if constexpr (N == 1) *p = v; else v.store(p);
}
template <int N>
PATINA_INLINE void store_n(int32_t* p, vint<N> v) {
    if constexpr (N == 1) *p = v; else v.store(p);
}

PATINA_END_TARGET
