// The radiance cache's generations (docs/radiance-cache.md, "Generations"): a region's cache
// points and kept hemispheres (cache_regions.h) serve every sample of its pixels, so their
// noise is shared by all of them and more samples did not average it out (cache-studio's
// soft patches a region wide: sd 0.0041 over 16 x 16-pixel squares at 64 and at 256 spp
// alike). A render's passes are grouped into generations of about kCacheGenerationSamples
// samples a pixel; each generation builds the regions again from numbers of its own, and a
// pixel's samples average over the generations, so the shared noise falls as
// 1 / sqrt(generations) -- as a progressive renderer restarts its caches each iteration
// with fresh random numbers. Generation 0 uses the numbers a render had before generations,
// so a render of at most one generation's samples is the same image, at the same cost.
#pragma once

#include <algorithm>
#include <cstdint>

#include "render/samplers/rng.h"

namespace patina {

// 16: the bench renders `cache` at 16 spp, one generation (its cost and image unchanged);
// each further 16 samples a pixel pay one more build of every region.
constexpr int kCacheGenerationSamples = 16;

// The passes a generation holds, for passes of pass_samples samples: as many as fit in
// kCacheGenerationSamples, at least one (the adaptive sampler's one pattern a pass: 16).
inline int cache_passes_per_generation(int pass_samples) {
    return std::max(1, kCacheGenerationSamples / std::max(pass_samples, 1));
}

// The seed of a generation's regions' pre-pass streams: generation 0's is the render's own.
inline uint32_t cache_generation_seed(uint32_t seed, int generation) {
    return generation == 0 ? seed : hash_u32(seed ^ (0x632be5abu * static_cast<uint32_t>(generation)));
}

// Where in its pixel (x or y: dim 0 or 1) a generation's pre-pass ray passes: generation 0
// through the centre, the others at a point drawn by the pixel's stream key, so the cache
// points' places change too and what their placement shares averages out as well.
inline float cache_prepass_offset(int generation, uint32_t pixel_key, uint32_t dim) {
    return generation == 0 ? 0.5f : uniform(hash_u32(pixel_key ^ 0x1f83d9abu), dim);
}

}  // namespace patina
