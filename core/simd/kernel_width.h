// The vocabulary of a kernel translation unit, compiled for one SIMD width. Each kernel
// family has a *_w{1,4,8,16}.cpp per width that defines PATINA_KERNEL_WIDTH, with that
// width's compiler flags, and includes the family's *_impl.h; every *_impl.h includes this
// header and writes its kernels once in terms of what it defines:
//   N             the SIMD width (1, 4, 8 or 16); in render/accel/ the packet code takes it as K
//   F, I, B, V3   vfloat<N>, vint<N>, vbool<N>, Vec3<vfloat<N>>
//   enter_kernel  first thing in a kernel entry point (see core/simd/upper_state.h)
//   for_blocks    a loop over blocks of N rows, the last one partial
//   load_rows ... N rows of (n, 3) arrays or N lanes of (n,) arrays, the last block
//                 through zero-padded copies (core/simd/rows.h)
//   grow          a work array at least n long, its memory kept from call to call
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "core/simd/rows.h"
#include "core/simd/simd.h"
#include "core/simd/upper_state.h"
#include "core/vec3.h"

#ifndef PATINA_KERNEL_WIDTH
#error "define PATINA_KERNEL_WIDTH (1, 4, 8 or 16) before including a kernel header (*_impl.h)"
#endif

PATINA_BEGIN_TARGET
namespace kernel_width {

constexpr int N = PATINA_KERNEL_WIDTH;
static_assert(N == 1 || N == 4 || N == 8 || N == 16, "kernels are compiled for widths 1, 4, 8 and 16");
using F = vfloat<N>;
using I = vint<N>;
using B = vbool<N>;
using V3 = Vec3<F>;

// Code at widths 1 and 4 is legacy SSE: it first clears the AVX upper state (upper_state.h).
PATINA_INLINE void enter_kernel() {
    if constexpr (N < 8) clear_upper_state();
}

// body(i, lanes) for the blocks [i, i + lanes) of n rows, lanes = N but in the last block.
template <class Body>
inline void for_blocks(size_t n, Body body) {
    for (size_t i = 0; i < n; i += N) body(i, static_cast<int>(std::min<size_t>(N, n - i)));
}

// Always inlined: left to the compiler it was called out of line from the material kinds'
// evaluation loops (render/materials/material_impl.h), 0.5% more instructions in `path`.
PATINA_INLINE V3 load_rows(const float* p, size_t i, int lanes) {
    V3 d;
    rows::load3<N>(p, i, lanes, d.x, d.y, d.z);
    return d;
}
PATINA_INLINE F load_lanes(const float* p, size_t i, int lanes) { return rows::load1<N>(p, i, lanes); }
PATINA_INLINE void store_rows(float* p, size_t i, int lanes, const V3& v) {
    rows::store3<N>(p, i, lanes, v.x, v.y, v.z);
}
PATINA_INLINE void store_rows(float* p, size_t i, int lanes, F x, F y, F z) { rows::store3<N>(p, i, lanes, x, y, z); }
PATINA_INLINE void store_lanes(float* p, size_t i, int lanes, F v) { rows::store1<N>(p, i, lanes, v); }

template <class T>
inline T* grow(std::vector<T>& v, size_t n) {
    if (v.size() < n) v.resize(n);
    return v.data();
}

}  // namespace kernel_width
PATINA_END_TARGET
