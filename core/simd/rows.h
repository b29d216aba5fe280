// Moving W lanes between SIMD registers and (n, 3) row arrays or (n,) arrays, with the
// last, partial block of an array read from and written through zero-padded copies.
#pragma once

#include <algorithm>
#include <cstddef>

#include "core/simd/simd.h"

PATINA_BEGIN_TARGET
namespace rows {

template <int W>
PATINA_INLINE void load3(const float* p, size_t i, int lanes, vfloat<W>& x, vfloat<W>& y, vfloat<W>& z) {
    if (lanes == W) {
        load_xyz(p + 3 * i, x, y, z);
    } else {
        float pad[3 * W] = {};
        std::copy(p + 3 * i, p + 3 * (i + lanes), pad);
        load_xyz(pad, x, y, z);
    }
}

template <int W>
PATINA_INLINE vfloat<W> load1(const float* p, size_t i, int lanes) {
    if (lanes == W) return load_n<W>(p + i);
    float pad[W] = {};
    std::copy(p + i, p + i + lanes, pad);
    return load_n<W>(pad);
}

template <int W>
PATINA_INLINE void store3(float* p, size_t i, int lanes, vfloat<W> x, vfloat<W> y, vfloat<W> z) {
    if (lanes == W) {
        store_xyz(p + 3 * i, x, y, z);
        return;
    }
    float tmp[3 * W];
    store_xyz(tmp, x, y, z);
    std::copy(tmp, tmp + 3 * lanes, p + 3 * i);
}

template <int W>
PATINA_INLINE void store1(float* p, size_t i, int lanes, vfloat<W> v) {
    if (lanes == W) {
        store_n<W>(p + i, v);
        return;
    }
    float tmp[W];
    store_n<W>(tmp, v);
    std::copy(tmp, tmp + lanes, p + i);
}

}  // namespace rows
PATINA_END_TARGET
