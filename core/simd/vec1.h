// Width 1: the scalar path is plain float / int32_t / bool, so a kernel written
// as `template <int N>` is ordinary scalar code at N = 1. These overloads give
// float the same free-function vocabulary as vfloat4 / vfloat8.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#include "target.h"

PATINA_BEGIN_TARGET

PATINA_INLINE float select(bool m, float a, float b) { return m ? a : b; }
PATINA_INLINE int32_t select(bool m, int32_t a, int32_t b) { return m ? a : b; }
PATINA_INLINE bool select(bool m, bool a, bool b) { return m ? a : b; }
PATINA_INLINE bool any(bool m) { return m; }
PATINA_INLINE bool all(bool m) { return m; }
PATINA_INLINE bool none(bool m) { return !m; }
PATINA_INLINE int movemask(bool m) { return m ? 1 : 0; }
PATINA_INLINE bool andnot(bool a, bool b) { return !a && b; }  // (!a) & b

PATINA_INLINE float madd(float a, float b, float c) { return a * b + c; }
PATINA_INLINE float nmadd(float a, float b, float c) { return c - a * b; }
PATINA_INLINE float fmadd(float a, float b, float c) { return a * b + c; }  // see vec8_avx.h
PATINA_INLINE float min(float a, float b) { return a < b ? a : b; }  // minps: NaN gives b
PATINA_INLINE float max(float a, float b) { return a > b ? a : b; }  // maxps: NaN gives b
PATINA_INLINE int32_t min(int32_t a, int32_t b) { return a < b ? a : b; }
PATINA_INLINE int32_t max(int32_t a, int32_t b) { return a > b ? a : b; }
PATINA_INLINE float abs(float a) { return std::fabs(a); }
PATINA_INLINE float floor(float a) { return std::floor(a); }
PATINA_INLINE float sqrt_exact(float a) { return std::sqrt(a); }
PATINA_INLINE float clamp(float x, float lo, float hi) { return min(max(x, lo), hi); }

PATINA_INLINE uint32_t as_bits(float a) {
    uint32_t u;
    std::memcpy(&u, &a, 4);
    return u;
}
PATINA_INLINE float from_bits(uint32_t u) {
    float a;
    std::memcpy(&a, &u, 4);
    return a;
}
PATINA_INLINE float copysign(float mag, float sgn) { return std::copysign(mag, sgn); }
PATINA_INLINE float xorsign(float a, float sgn) {
    return from_bits(as_bits(a) ^ (as_bits(sgn) & 0x80000000u));
}
PATINA_INLINE bool signbit(float a) { return (as_bits(a) >> 31) != 0; }
PATINA_INLINE bool isnan(float a) { return a != a; }

// Bit operations on 32-bit lanes as on unsigned integers (hashes): logical shift right and
// a multiply that wraps modulo 2^32 (int32_t overflow would be undefined).
PATINA_INLINE int32_t srl(int32_t a, int s) { return static_cast<int32_t>(static_cast<uint32_t>(a) >> s); }
PATINA_INLINE int32_t mul_wrap(int32_t a, int32_t b) {
    return static_cast<int32_t>(static_cast<uint32_t>(a) * static_cast<uint32_t>(b));
}
PATINA_INLINE int32_t to_int_trunc(float a) { return static_cast<int32_t>(a); }
PATINA_INLINE int32_t as_int(float a) { return static_cast<int32_t>(as_bits(a)); }
PATINA_INLINE float as_float(int32_t a) { return from_bits(static_cast<uint32_t>(a)); }
PATINA_INLINE float to_float(int32_t a) { return static_cast<float>(a); }

PATINA_INLINE float gather(const float* base, int32_t index) { return base[index]; }
PATINA_INLINE int32_t gather(const int32_t* base, int32_t index) { return base[index]; }
PATINA_INLINE float gather(const float* base, int32_t index, bool active) {
    return active ? base[index] : 0.0f;
}

PATINA_INLINE float lane(float v, int) { return v; }

// Three consecutive floats at base[index]: one row of an RGB table.
PATINA_INLINE void gather3(const float* base, int32_t index, float& a, float& b, float& c) {
    a = base[index];
    b = base[index + 1];
    c = base[index + 2];
}

// Three-component rows (x y z x y z ...) to and from one value per lane.
PATINA_INLINE void load_xyz(const float* p, float& x, float& y, float& z) {
    x = p[0];
    y = p[1];
    z = p[2];
}
PATINA_INLINE void store_xyz(float* p, float x, float y, float z) {
    p[0] = x;
    p[1] = y;
    p[2] = z;
}
PATINA_INLINE int32_t lane(int32_t v, int) { return v; }
PATINA_INLINE bool lane(bool v, int) { return v; }

PATINA_END_TARGET
