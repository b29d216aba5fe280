// The numbers a path draws, from its stream key and sample index (CameraSample), for each
// use at each bounce (rng.h's RandomDim):
//
// - SamplerKind::Sobol: the stream (a pixel) is one Owen-scrambled Sobol sequence
//   (render/sobol.h), the sample index its point, each use one Sobol dimension: the camera's
//   four (pixel x, y, lens u, v: dimensions 0-3, so the pixel positions of a pixel's first
//   2^m samples are a (0, m, 2)-net) at the first bounce, then seven a bounce (light pick, u,
//   v, BRDF pick, u, v, roulette). Each (stream, dimension) has its own scramble seed, so
//   pixels are decorrelated and a pixel's samples are stratified in every projection the
//   sequence stratifies. Dimensions past the generated table (bounce 17 on) are padded
//   with the independent numbers below.
// - SamplerKind::Independent: a hash of (sample_key(stream, index), dimension), rng.h.
//
// Both are functions of (stream, index, bounce, use) only: the same whatever the thread,
// the tile order or the SIMD width (integers throughout; the lanes version gives each lane
// the scalar bits).
#pragma once

#include <cstdint>
#include <type_traits>

#include "core/simd/simd.h"
#include "render/integrator.h"
#include "render/rng.h"
#include "render/sobol.h"

PATINA_BEGIN_TARGET

inline constexpr uint32_t kCameraDims = kDimLightPick;                       // pixel x, y, lens u, v
inline constexpr uint32_t kBounceDims = kDimRoulette - kDimLightPick + 1;     // light, BRDF, roulette
inline constexpr uint32_t kNoSobolDim = 0xffffffffu;                          // a use Sobol does not cover

// The Sobol dimension of use d at `bounce` (kNoSobolDim beyond the table, or for a camera
// use after the first bounce).
inline uint32_t sobol_dimension(int bounce, RandomDim d) {
    uint32_t dim;
    if (d < kDimLightPick)
        dim = bounce == 0 ? static_cast<uint32_t>(d) : kNoSobolDim;
    else
        dim = kCameraDims + static_cast<uint32_t>(bounce) * kBounceDims + (d - kDimLightPick);
    return dim < static_cast<uint32_t>(sobol::kDimensions) ? dim : kNoSobolDim;
}

// The scramble seed of dimension `dim` of stream `key`.
inline uint32_t scramble_seed(uint32_t key, uint32_t dim) { return hash_u32(key ^ hash_u32(dim + 0x5851f42du)); }

inline float unit_float(uint32_t bits) { return static_cast<float>(bits >> 8) * (1.0f / 16777216.0f); }

inline float sample_uniform(SamplerKind kind, uint32_t key, uint32_t index, int bounce, RandomDim d) {
    const uint32_t dim = kind == SamplerKind::Sobol ? sobol_dimension(bounce, d) : kNoSobolDim;
    if (dim == kNoSobolDim) return bounce_uniform(sample_key(key, index), bounce, d);
    return unit_float(sobol::owen_scramble(sobol::point_bits(index, static_cast<int>(dim)), scramble_seed(key, dim)));
}

// The same for N paths at once (keys and indices: uint32 bits in int32 lanes); index_bits:
// the bit length of the largest index among them.
template <class I>
PATINA_INLINE auto sample_uniform_lanes(SamplerKind kind, I keys, I index, int index_bits, int bounce, RandomDim d) {
    const uint32_t dim = kind == SamplerKind::Sobol ? sobol_dimension(bounce, d) : kNoSobolDim;
    if (dim == kNoSobolDim) {
        const I step = mul_wrap(index, I(static_cast<int32_t>(0x85ebca6bu)));
        I sum;  // keys + step modulo 2^32 (int32_t overflow would be undefined at width 1)
        if constexpr (std::is_same_v<I, int32_t>)
            sum = static_cast<int32_t>(static_cast<uint32_t>(keys) + static_cast<uint32_t>(step));
        else
            sum = keys + step;
        const I path = hash_lanes(sum);
        return bounce_uniform_lanes(path, bounce, d);
    }
    const I seed = hash_lanes(keys ^ I(static_cast<int32_t>(hash_u32(dim + 0x5851f42du))));
    const I bits = sobol::owen_scramble_lanes(sobol::point_bits_lanes(index, static_cast<int>(dim), index_bits), seed);
    return to_float(srl(bits, 8)) * decltype(to_float(bits))(1.0f / 16777216.0f);
}

// The bit length of x (0 for 0).
inline int bit_length(uint32_t x) {
    int n = 0;
    for (; x != 0; x >>= 1) ++n;
    return n;
}

PATINA_END_TARGET
