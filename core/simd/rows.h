// Moving N lanes between SIMD registers and (n, 3) row arrays or (n,) arrays, with the
// last, partial block of an array read from and written through zero-padded copies.
#pragma once

#include <algorithm>
#include <cstddef>

#include "core/simd/simd.h"

PATINA_BEGIN_TARGET
namespace rows {

template <int N>
PATINA_INLINE void load3(const float* p, size_t i, int lanes, vfloat<N>& x, vfloat<N>& y, vfloat<N>& z) {
    if (lanes == N) {
        load_xyz(p + 3 * i, x, y, z);
    } else {
        float pad[3 * N] = {};
        std::copy(p + 3 * i, p + 3 * (i + lanes), pad);
        load_xyz(pad, x, y, z);
    }
}

template <int N>
PATINA_INLINE vfloat<N> load1(const float* p, size_t i, int lanes) {
    if (lanes == N) return load_n<N>(p + i);
    float pad[N] = {};
    std::copy(p + i, p + i + lanes, pad);
    return load_n<N>(pad);
}

template <int N>
PATINA_INLINE void store3(float* p, size_t i, int lanes, vfloat<N> x, vfloat<N> y, vfloat<N> z) {
    if (lanes == N) {
        store_xyz(p + 3 * i, x, y, z);
        return;
    }
    float tmp[3 * N];
    store_xyz(tmp, x, y, z);
    std::copy(tmp, tmp + 3 * lanes, p + 3 * i);
}

template <int N>
PATINA_INLINE void store1(float* p, size_t i, int lanes, vfloat<N> v) {
    if (lanes == N) {
        store_n<N>(p + i, v);
        return;
    }
    float tmp[N];
    store_n<N>(tmp, v);
    std::copy(tmp, tmp + lanes, p + i);
}

}  // namespace rows
PATINA_END_TARGET
