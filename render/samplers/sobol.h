// Owen-scrambled Sobol points of the (0, 2)-sequence: the low-discrepancy numbers of the
// sobol sampler (render/samplers/sample_numbers.h), which draws every pair of numbers from it.
//
// Point i of dimension d is the XOR of the direction numbers V_d,k of the set bits k of i
// (the direct order, not the Gray-code one: the first 2^m points are then the same set as
// in Gray-code order). Sobol's first two dimensions: van der Corput (V_0,k = 2^-(k+1)) and
// the one of the primitive polynomial x + 1 (m_k = 2 m_{k-1} ^ m_{k-1}, m_1 = 1: V_1,k =
// V_1,k-1 ^ V_1,k-1 / 2), together a (0, 2)-sequence: any aligned block of 2^m points is a
// (0, m, 2)-net, one point in each of the 2^a x 2^(m-a) elementary intervals.
//
// The points are then Owen-scrambled (a nested uniform scramble, Owen 1995): bit b of the
// value is flipped or kept by a random bit drawn for the node of the binary tree that the
// bits above b name, so every elementary interval is mapped onto one of the same size as a
// whole: a (t, m, s)-net stays one, and the points are uniform in [0, 1). The node's bit is
// a hash of (node, seed): one seed per use and pixel gives every pixel its own scramble,
// which decorrelates the pixels' errors. The top 24 bits are scrambled, as many as a float
// in [0, 1) keeps: the top kOwenLevels bit by bit, the rest flipped together by one hash of
// the node above them (a digital shift of each interval of width 2^-kOwenLevels: a nested
// scramble still, with half the hashes; it differs from a full one only for more than
// 2^kOwenLevels points of a pixel).
//
// Integer-only arithmetic, the same at every SIMD width: the lanes version gives each lane
// the bits the scalar one gives.
#pragma once

#include <array>
#include <cstdint>
#include <type_traits>

#include "core/simd/simd.h"
#include "render/samplers/rng.h"

PATINA_BEGIN_TARGET
namespace sobol {

inline constexpr int kDimensions = 2;
inline constexpr int kBits = 32;        // indices of up to 2^32 points
inline constexpr int kScrambledBits = 24;  // the bits a float in [0, 1) keeps
inline constexpr int kOwenLevels = 12;     // of them, scrambled bit by bit

using Matrices = std::array<std::array<uint32_t, kBits>, kDimensions>;

constexpr Matrices make_matrices() {
    Matrices v{};
    for (int k = 0; k < kBits; ++k) {
        v[0][k] = 1u << (kBits - 1 - k);
        v[1][k] = k == 0 ? 1u << (kBits - 1) : v[1][k - 1] ^ (v[1][k - 1] >> 1);
    }
    return v;
}

// Internal linkage (const, not inline), a copy a translation unit: an inline variable is a
// GNU "unique" symbol, which the width-16 objects' symbol localisation (CMakeLists.txt,
// patina_private_avx512_object) leaves global, so two of them would clash at link time.
constexpr Matrices kMatrices = make_matrices();

// The unscrambled point `index` of dimension d < kDimensions, as 32 fraction bits.
inline uint32_t point_bits(uint32_t index, int d) {
    uint32_t x = 0;
    for (int k = 0; index != 0; ++k, index >>= 1)
        if (index & 1u) x ^= kMatrices[d][k];
    return x;
}

// The bits flipped together below the top kOwenLevels.
inline constexpr uint32_t kShiftMask = ((1u << (kScrambledBits - kOwenLevels)) - 1u) << (kBits - kScrambledBits);

// Owen's nested uniform scramble of the top kScrambledBits of x. Node of bit b: the bits
// above it with a leading 1 (the root is 1), unique over the tree's levels.
inline uint32_t owen_scramble(uint32_t x, uint32_t seed) {
    uint32_t out = x;
    for (int b = kBits - 1; b >= kBits - kOwenLevels; --b) {
        const uint32_t node = b == kBits - 1 ? 1u : (x >> (b + 1)) | (1u << (kBits - 1 - b));
        out ^= (hash_u32(node ^ seed) >> 31) << b;
    }
    const uint32_t node = (x >> (kBits - kOwenLevels)) | (1u << kOwenLevels);
    return out ^ (hash_u32(node ^ seed) & kShiftMask);
}

// The same for N lanes (uint32 bits in int32 lanes); dimension d is shared by the lanes.
// index_bits: the bit length of the largest index (fewer loop turns, the same bits).
// x << s on uint32 bits (at width 1 through uint32_t: int32_t overflow is undefined)
template <class I>
PATINA_INLINE I shift_left(I x, int s) {
    if constexpr (std::is_same_v<I, int32_t>)
        return static_cast<int32_t>(static_cast<uint32_t>(x) << s);
    else
        return x << s;
}

template <class I>
PATINA_INLINE I point_bits_lanes(I index, int d, int index_bits) {
    I x(0);
    for (int k = 0; k < index_bits; ++k) {
        const I bit = srl(index, k) & I(1);
        x = x ^ ((I(0) - bit) & I(static_cast<int32_t>(kMatrices[d][k])));
    }
    return x;
}

template <class I>
PATINA_INLINE I owen_scramble_lanes(I x, I seed) {
    I out = x;
    for (int b = kBits - 1; b >= kBits - kOwenLevels; --b) {
        const I node = b == kBits - 1 ? I(1) : srl(x, b + 1) | I(static_cast<int32_t>(1u << (kBits - 1 - b)));
        out = out ^ shift_left(srl(hash_lanes(node ^ seed), 31), b);
    }
    const I node = srl(x, kBits - kOwenLevels) | I(1 << kOwenLevels);
    return out ^ (hash_lanes(node ^ seed) & I(static_cast<int32_t>(kShiftMask)));
}

// --- the index shuffle: a nested scramble of the sample index ------------------------------
//
// Bit k of the index is flipped by a function of the bits above it, for its low
// kShuffleLevels bits (the bits above stay). Such a map permutes every aligned block of 2^m
// indices onto an aligned block of 2^m indices (m <= kShuffleLevels; onto itself past
// them), and any aligned block of 2^m points of a (0, 2)-sequence is a (0, m, 2)-net: a
// shuffled pixel's first 2^m samples are still a net. Shuffled by independent seeds, two
// uses' sequences pair their points at random (Kollig and Keller's padding), so each 2-D use
// is the (0, 2)-sequence's net while different uses are decorrelated.
//
// The flips come from Laine and Karras's observation: on the bit-reversed index (the low
// bits on top), adding a seed, multiplying by an odd number, and x ^= x * even each change a
// bit by a function of the bits below it only, and are invertible; their composition, on the
// top kShuffleLevels bits, is a seeded nested scramble with a few multiplications in place
// of a hash a level (the shuffle only decorrelates the uses: the values keep the hashed
// scramble above). Tests: tests/cpp/render/samplers/test_sobol.cpp.
inline constexpr int kShuffleLevels = 12;  // permutes within blocks of 4096 samples
inline constexpr uint32_t kShuffleTop = ~0u << (kBits - kShuffleLevels);

inline uint32_t reverse_bits(uint32_t x) {
    x = (x >> 16) | (x << 16);
    x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    return ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
}

inline uint32_t shuffle_index(uint32_t index, uint32_t seed) {
    const uint32_t r = reverse_bits(index);
    uint32_t x = r + seed;
    x ^= x * 0x9e3779b8u;
    x *= (seed >> 8) | 1u;
    x ^= x * 0x7feb352cu;
    x ^= x * 0x846ca68au;
    return reverse_bits((x & kShuffleTop) | (r & ~kShuffleTop));
}

// x + y modulo 2^32 on uint32 bits (at width 1 through uint32_t: int32_t overflow is undefined)
template <class I>
PATINA_INLINE I add_wrap(I x, I y) {
    if constexpr (std::is_same_v<I, int32_t>)
        return static_cast<int32_t>(static_cast<uint32_t>(x) + static_cast<uint32_t>(y));
    else
        return x + y;
}

template <class I>
PATINA_INLINE I swap_bits(I x, int s, uint32_t mask) {
    const I m(static_cast<int32_t>(mask));
    return (srl(x, s) & m) | shift_left(x & m, s);
}

template <class I>
PATINA_INLINE I reverse_bits_lanes(I x) {
    x = srl(x, 16) | shift_left(x, 16);
    x = swap_bits(x, 8, 0x00ff00ffu);
    x = swap_bits(x, 4, 0x0f0f0f0fu);
    x = swap_bits(x, 2, 0x33333333u);
    return swap_bits(x, 1, 0x55555555u);
}

template <class I>
PATINA_INLINE I shuffle_index_lanes(I index, I seed) {
    const I r = reverse_bits_lanes(index);
    I x = add_wrap(r, seed);
    x = x ^ mul_wrap(x, I(static_cast<int32_t>(0x9e3779b8u)));
    x = mul_wrap(x, srl(seed, 8) | I(1));
    x = x ^ mul_wrap(x, I(static_cast<int32_t>(0x7feb352cu)));
    x = x ^ mul_wrap(x, I(static_cast<int32_t>(0x846ca68au)));
    const I top(static_cast<int32_t>(kShuffleTop));
    return reverse_bits_lanes((x & top) | (r & I(static_cast<int32_t>(~kShuffleTop))));
}

}  // namespace sobol
PATINA_END_TARGET
