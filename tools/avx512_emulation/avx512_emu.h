// Verification harness only (tools/avx512_emulation/run.py): the AVX-512 intrinsics that
// core/simd/vec16_avx512.h uses, emulated by SIMDe (Debian: libsimde-dev) on a CPU without
// AVX-512, so the width-16 code can be tested lane by lane there. SIMDe 0.7.4 lacks the few
// defined below; they are written from Intel's definitions (gathers, cvtt: INT32_MIN for NaN
// and out of range, sra: counts above 31 fill with the sign). Never part of a real build.
#pragma once
#define SIMDE_ENABLE_NATIVE_ALIASES
#include <simde/x86/avx512.h>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <climits>
#undef _kand_mask16
#define _kand_mask16 emu_kand
static inline __mmask16 emu_kand(__mmask16 a, __mmask16 b) { return (__mmask16)(a & b); }
#undef _kor_mask16
#define _kor_mask16 emu_kor
static inline __mmask16 emu_kor(__mmask16 a, __mmask16 b) { return (__mmask16)(a | b); }
#undef _kxor_mask16
#define _kxor_mask16 emu_kxor
static inline __mmask16 emu_kxor(__mmask16 a, __mmask16 b) { return (__mmask16)(a ^ b); }
#undef _knot_mask16
#define _knot_mask16 emu_knot
static inline __mmask16 emu_knot(__mmask16 a) { return (__mmask16)(~a); }
#undef _kandn_mask16
#define _kandn_mask16 emu_kandn
static inline __mmask16 emu_kandn(__mmask16 a, __mmask16 b) { return (__mmask16)(~a & b); }
static inline __m256 emu_extractf32x8(__m512 a, int i) { float t[16]; _mm512_storeu_ps(t, a); return _mm256_loadu_ps(t + 8 * i); }
#undef _mm512_extractf32x8_ps
#define _mm512_extractf32x8_ps(a, i) emu_extractf32x8(a, i)
static inline __m256i emu_extracti32x8(__m512i a, int i) { int32_t t[16]; _mm512_storeu_si512(t, a); return _mm256_loadu_si256((const __m256i*)(t + 8 * i)); }
#undef _mm512_extracti32x8_epi32
#define _mm512_extracti32x8_epi32(a, i) emu_extracti32x8(a, i)
static inline __m512 _mm512_i32gather_ps_emu(__m512i idx, const void* base, int) { int32_t i[16]; float r[16]; _mm512_storeu_si512(i, idx); for (int j = 0; j < 16; ++j) r[j] = ((const float*)base)[i[j]]; return _mm512_loadu_ps(r); }
#undef _mm512_i32gather_ps
#define _mm512_i32gather_ps(i, b, s) _mm512_i32gather_ps_emu(i, b, s)
static inline __m512i _mm512_i32gather_epi32_emu(__m512i idx, const void* base, int) { int32_t i[16], r[16]; _mm512_storeu_si512(i, idx); for (int j = 0; j < 16; ++j) r[j] = ((const int32_t*)base)[i[j]]; return _mm512_loadu_si512(r); }
#undef _mm512_i32gather_epi32
#define _mm512_i32gather_epi32(i, b, s) _mm512_i32gather_epi32_emu(i, b, s)
static inline __m512 _mm512_mask_i32gather_ps_emu(__m512 src, __mmask16 k, __m512i idx, const void* base, int) { int32_t i[16]; float r[16]; _mm512_storeu_si512(i, idx); _mm512_storeu_ps(r, src); for (int j = 0; j < 16; ++j) if ((k >> j) & 1) r[j] = ((const float*)base)[i[j]]; return _mm512_loadu_ps(r); }
#undef _mm512_mask_i32gather_ps
#define _mm512_mask_i32gather_ps(s, k, i, b, sc) _mm512_mask_i32gather_ps_emu(s, k, i, b, sc)
static inline __m512i emu_sra(__m512i a, __m128i c) { int32_t t[16]; _mm512_storeu_si512(t, a); long long s = _mm_cvtsi128_si64(c); for (int j = 0; j < 16; ++j) t[j] = s > 31 ? (t[j] < 0 ? -1 : 0) : (t[j] >> s); return _mm512_loadu_si512(t); }
#undef _mm512_sra_epi32
#define _mm512_sra_epi32(a, c) emu_sra(a, c)
static inline __m512i emu_cvtt(__m512 a) { float t[16]; int32_t r[16]; _mm512_storeu_ps(t, a); for (int j = 0; j < 16; ++j) r[j] = (std::isnan(t[j]) || t[j] >= 2147483648.0f || t[j] < -2147483648.0f) ? INT_MIN : (int32_t)t[j]; return _mm512_loadu_si512(r); }
#undef _mm512_cvttps_epi32
#define _mm512_cvttps_epi32(a) emu_cvtt(a)
static inline __m512 emu_cvtepi32(__m512i a) { int32_t t[16]; float r[16]; _mm512_storeu_si512(t, a); for (int j = 0; j < 16; ++j) r[j] = (float)t[j]; return _mm512_loadu_ps(r); }
#undef _mm512_cvtepi32_ps
#define _mm512_cvtepi32_ps(a) emu_cvtepi32(a)
