// Which instruction set this translation unit is compiled for.
//
// Kernels are compiled several times (scalar, SSE4.1, AVX2+FMA, AVX-512), each time with
// different compiler flags. Everything in the SIMD headers lives in an inline
// namespace named after the target, so the copies get different symbol names and
// the linker can never pick an AVX2-compiled helper for the scalar path (the
// classic multi-versioning ODR trap). Code outside simply writes patina::vfloat4.
#pragma once

#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512DQ__) && defined(__AVX512BW__) && \
    defined(__FMA__)
#define PATINA_HAS_AVX512 1
#define PATINA_HAS_AVX2 1
#define PATINA_TARGET_NS target_avx512
// GCC 12's AVX-512 intrinsics initialise their "undefined" vectors from themselves
// (`__m512 __Y = __Y;`), which -W(maybe-)uninitialized reports wherever they are inlined (GCC
// bug 105593, fixed in 13). The warning is judged at the header's own lines, so the header is
// read here, first, with it off; every other warning stays on in the width-16 units.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>
#pragma GCC diagnostic pop
#endif
#elif defined(__AVX2__) && defined(__FMA__)
#define PATINA_HAS_AVX2 1
#define PATINA_TARGET_NS target_avx2
#elif defined(__SSE4_1__)
#define PATINA_TARGET_NS target_sse4
#else
#define PATINA_TARGET_NS target_scalar
#endif

#if defined(__SSE4_1__)
#define PATINA_HAS_SSE4 1
#endif

#define PATINA_BEGIN_TARGET \
    namespace patina {      \
    inline namespace PATINA_TARGET_NS {
#define PATINA_END_TARGET \
    }                     \
    }

#if defined(_MSC_VER)
#define PATINA_INLINE __forceinline
#else
#define PATINA_INLINE inline __attribute__((always_inline))
#endif
