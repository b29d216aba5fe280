// The numbers a path draws, from its stream key and sample index (CameraSample), for each
// use at each bounce (render/samplers/rng.h's RandomDim):
//
// - SamplerKind::Sobol: a padded Owen-scrambled Sobol sampler. The uses come in groups: the
//   pairs (pixel x, y), (lens u, v), (light u, v) and (BRDF u, v), and the single uses light
//   pick, BRDF pick and Russian roulette. Every group of every bounce draws from the same
//   (0, 2)-sequence, Sobol's first two dimensions (render/samplers/sobol.h; a single use: the first),
//   with the stream's sample index shuffled by the group's own nested scramble
//   (sobol::shuffle_index) and the values Owen-scrambled with the group's own seeds. So each
//   pair's first 2^m samples of a pixel are a (0, m, 2)-net, one in each of the 2^a x
//   2^(m-a) strata, each single use is stratified in 2^m intervals, and the groups are
//   paired at random, as Kollig and Keller's padding and pbrt-v4's padded Sobol sampler do:
//   unlike consecutive dimensions of one Sobol sequence, whose higher pairs have 2-D
//   projections far from a (0, 2)-net at a pixel's sample counts, every pair is as well
//   stratified as the first. Every bounce is covered (no table to run out of).
// - SamplerKind::Independent: a hash of (sample_key(stream, index), dimension), render/samplers/rng.h.
//
// Both are functions of (stream, index, bounce, use) only: the same whatever the thread,
// the tile order or the SIMD width (integers throughout; the lanes version gives each lane
// the scalar bits).
#pragma once

#include <cstdint>

#include "core/simd/simd.h"
#include "render/integrators/integrator.h"
#include "render/samplers/rng.h"
#include "render/samplers/sobol.h"

PATINA_BEGIN_TARGET

// A use's group: its first use (the pair's first, or the use itself) and its component
// (0 or 1: the (0, 2)-sequence's dimension it draws).
struct SobolGroup {
    uint32_t id;  // unique over (bounce, group): bounce * kDimsPerBounce + the group's first use
    int component;
};

inline SobolGroup sobol_group(int bounce, RandomDim d) {
    const bool second = d == kDimPixelY || d == kDimLensV || d == kDimLightV || d == kDimBsdfV;
    return {static_cast<uint32_t>(bounce) * kDimsPerBounce + d - (second ? 1u : 0u), second ? 1 : 0};
}

// The pixel position's group keeps the sequence's order (the pairing is what the shuffles
// randomise: one group needs none, and the pixel sampler draws its numbers one at a time).
inline constexpr uint32_t kPixelGroup = kDimPixelX;

// The seeds of a group of stream `key`: its index shuffle's, and its values' scramble (one
// a component).
inline uint32_t shuffle_seed(uint32_t key, uint32_t group) { return hash_u32(key ^ hash_u32(group + 0x2545f491u)); }
inline uint32_t scramble_seed(uint32_t key, uint32_t group, int component) {
    return hash_u32(key ^ hash_u32(2 * group + static_cast<uint32_t>(component) + 0x5851f42du));
}

inline float unit_float(uint32_t bits) { return static_cast<float>(bits >> 8) * (1.0f / 16777216.0f); }

inline float sample_uniform(SamplerKind kind, uint32_t key, uint32_t index, int bounce, RandomDim d) {
    if (kind != SamplerKind::Sobol) return bounce_uniform(sample_key(key, index), bounce, d);
    const SobolGroup g = sobol_group(bounce, d);
    const uint32_t shuffled = g.id == kPixelGroup ? index : sobol::shuffle_index(index, shuffle_seed(key, g.id));
    return unit_float(sobol::owen_scramble(sobol::point_bits(shuffled, g.component), scramble_seed(key, g.id, g.component)));
}

// The same for N paths at once (keys and indices: uint32 bits in int32 lanes); index_bits:
// the bit length of the largest index among them.
template <class I>
PATINA_INLINE auto sample_uniform_lanes(SamplerKind kind, I keys, I index, int index_bits, int bounce, RandomDim d) {
    if (kind != SamplerKind::Sobol) {
        const I path = hash_lanes(sobol::add_wrap(keys, mul_wrap(index, I(static_cast<int32_t>(0x85ebca6bu)))));
        return bounce_uniform_lanes(path, bounce, d);
    }
    const SobolGroup g = sobol_group(bounce, d);
    const I shuffle = hash_lanes(keys ^ I(static_cast<int32_t>(hash_u32(g.id + 0x2545f491u))));
    const I shuffled = g.id == kPixelGroup ? index : sobol::shuffle_index_lanes(index, shuffle);
    const I seed = hash_lanes(keys ^ I(static_cast<int32_t>(
                                         hash_u32(2 * g.id + static_cast<uint32_t>(g.component) + 0x5851f42du))));
    // the shuffle keeps the bits above its levels, and any below them may be set
    const int bits = index_bits > sobol::kShuffleLevels ? index_bits : sobol::kShuffleLevels;
    const I value = sobol::owen_scramble_lanes(sobol::point_bits_lanes(shuffled, g.component, bits), seed);
    return to_float(srl(value, 8)) * decltype(to_float(value))(1.0f / 16777216.0f);
}

// The bit length of x (0 for 0).
inline int bit_length(uint32_t x) {
    int n = 0;
    for (; x != 0; x >>= 1) ++n;
    return n;
}

PATINA_END_TARGET
