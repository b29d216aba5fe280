// The radiance cache's masks (docs/radiance-cache.md): 128 x 128 bit matrices over a
// point's hemisphere texels, one 128-bit SIMD word per row, so "fill what is still free and
// not unknown" is three logical operations on 128 texels at once instead of a z-test per
// texel. A hemisphere of R x R texels (R <= 128) uses the first R rows and the low R bits of
// each. The row type is the compiler's 128-bit vector (SSE2 on every x86-64 target, no
// intrinsics); bit x of a row is bit x % 64 of lane x / 64.
#pragma once

#include <cstdint>
#include <cstring>

#include "core/simd/target.h"

PATINA_BEGIN_TARGET
namespace cache {

constexpr int kMaskSide = 128;

typedef uint64_t Row128 __attribute__((vector_size(16)));

// Bits [x0, x1) of a row set (0 <= x0 <= x1 <= 128).
PATINA_INLINE Row128 span_bits(int x0, int x1) {
    auto lane = [](int a, int b) -> uint64_t {  // bits [a, b) of one 64-bit lane, a, b in [0, 64]
        if (b <= a) return 0;
        const uint64_t hi = b >= 64 ? ~uint64_t{0} : ((uint64_t{1} << b) - 1);
        const uint64_t lo = a >= 64 ? ~uint64_t{0} : ((uint64_t{1} << a) - 1);
        return hi & ~lo;
    };
    auto c = [](int v, int lo, int hi) { return v < lo ? lo : (v > hi ? hi : v); };
    Row128 r = {lane(c(x0, 0, 64), c(x1, 0, 64)), lane(c(x0 - 64, 0, 64), c(x1 - 64, 0, 64))};
    return r;
}

PATINA_INLINE bool row_empty(Row128 r) { return (r[0] | r[1]) == 0; }
PATINA_INLINE int row_count(Row128 r) { return __builtin_popcountll(r[0]) + __builtin_popcountll(r[1]); }

struct BitMask128 {
    alignas(16) Row128 rows[kMaskSide];

    void clear() { std::memset(rows, 0, sizeof(rows)); }
    bool test(int x, int y) const { return (rows[y][x >> 6] >> (x & 63)) & 1u; }
    void set(int x, int y) { rows[y][x >> 6] |= uint64_t{1} << (x & 63); }
    // every bit of the R x R square set
    void fill_square(int resolution) {
        clear();
        const Row128 full = span_bits(0, resolution);
        for (int y = 0; y < resolution; ++y) rows[y] = full;
    }
    int count(int resolution) const {
        int n = 0;
        for (int y = 0; y < resolution; ++y) n += row_count(rows[y]);
        return n;
    }
};

// Calls f(x) for each set bit of a row, lowest first.
template <class Fn>
PATINA_INLINE void for_each_bit(Row128 r, Fn f) {
    for (int l = 0; l < 2; ++l) {
        uint64_t w = r[l];
        while (w != 0) {
            f(64 * l + __builtin_ctzll(w));
            w &= w - 1;
        }
    }
}

}  // namespace cache
PATINA_END_TARGET
