// Counter-based random numbers: every number is a hash of (path key, dimension), so a
// path's numbers are fixed by (seed, pixel, sample, bounce, use) whatever the thread,
// the tile order or the SIMD width. That makes renders deterministic for a seed and
// bit-identical across widths (the kernels are), which the tests check.
#pragma once

#include <cstdint>

#include "core/simd/simd.h"

// Inside the target namespace: each ISA's copy has its own symbols (see core/simd/target.h).
PATINA_BEGIN_TARGET

// A 32-bit integer hash with low bias (C. Wellons, "Prospecting for hash functions", lowbias32).
inline uint32_t hash_u32(uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

// A stream's key (a pixel's, a corner's: render/samplers/sample_numbers.h), and the key of its
// sample `sample`; path_key(seed, pixel, sample) = sample_key(stream_key(seed, pixel), sample).
inline uint32_t stream_key(uint32_t seed, uint32_t stream) { return hash_u32(hash_u32(seed ^ 0x9e3779b9u) ^ stream); }
inline uint32_t sample_key(uint32_t stream, uint32_t sample) { return hash_u32(stream + sample * 0x85ebca6bu); }

inline uint32_t path_key(uint32_t seed, uint32_t pixel, uint32_t sample) {
    return sample_key(stream_key(seed, pixel), sample);
}

// Uniform in [0, 1): the top 24 bits of the hash.
inline float uniform(uint32_t key, uint32_t dim) {
    return static_cast<float>(hash_u32(key ^ hash_u32(dim + 0x632be5abu)) >> 8) * (1.0f / 16777216.0f);
}

// Dimensions a bounce uses: bounce * kDimsPerBounce + one of these.
enum RandomDim : uint32_t {
    kDimPixelX = 0, kDimPixelY, kDimLensU, kDimLensV,
    kDimLightPick, kDimLightU, kDimLightV, kDimBsdfPick, kDimBsdfU, kDimBsdfV, kDimRoulette,
    kDimsPerBounce = 16
};

inline float bounce_uniform(uint32_t key, int bounce, RandomDim d) {
    return uniform(key, static_cast<uint32_t>(bounce) * kDimsPerBounce + d);
}

// The same numbers for N keys at once (lanes hold the uint32 bits of the keys).
template <class I>
PATINA_INLINE I hash_lanes(I x) {
    x = x ^ srl(x, 16);
    x = mul_wrap(x, I(0x7feb352d));
    x = x ^ srl(x, 15);
    x = mul_wrap(x, I(static_cast<int32_t>(0x846ca68bu)));
    return x ^ srl(x, 16);
}

template <class I>
PATINA_INLINE auto bounce_uniform_lanes(I keys, int bounce, RandomDim d) {
    const uint32_t salt = hash_u32(static_cast<uint32_t>(bounce) * kDimsPerBounce + d + 0x632be5abu);
    const I h = hash_lanes(keys ^ I(static_cast<int32_t>(salt)));
    return to_float(srl(h, 8)) * decltype(to_float(h))(1.0f / 16777216.0f);
}

PATINA_END_TARGET
