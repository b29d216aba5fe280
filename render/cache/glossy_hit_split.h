// What split_glossy_hits (radiance_cache_impl.h) needs: which materials' hits a cache point's
// texel splits into more paths (marked by mark_split_materials, cache_stages_impl.h, per batch),
// how many, and the further paths' rays and the texels they belong to.
#pragma once

#include <cstdint>
#include <vector>

#include "core/simd/target.h"
#include "render/cache/ray_queue.h"

PATINA_BEGIN_TARGET
namespace cache {

struct GlossyHitSplit {
    // per material: whether a cache point's texel hit on it takes hit_paths paths from the hit
    // (empty: none, as for the guides, which need the light's shape only)
    std::vector<uint8_t> split_material;
    int hit_paths = 1;
    RayQueue rays;                // the further paths' rays
    std::vector<int32_t> texels;  // the texels split (a ray's `where`)
};

}  // namespace cache
PATINA_END_TARGET
