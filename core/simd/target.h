// Which instruction set this translation unit is compiled for.
//
// Kernels are compiled several times (scalar, SSE4.1, AVX2+FMA), each time with
// different compiler flags. Everything in the SIMD headers lives in an inline
// namespace named after the target, so the copies get different symbol names and
// the linker can never pick an AVX2-compiled helper for the scalar path (the
// classic multi-versioning ODR trap). Code outside simply writes patina::vfloat4.
#pragma once

#if defined(__AVX2__) && defined(__FMA__)
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
