// The regions' reconstructed hemispheres (region_hemisphere.h) a batch's members take instead
// of making queries of their own: indexed by block and by pixel when the batch starts
// (collect_queries, cache_stages_impl.h), those the batch uses added as stored_hemisphere
// finds them, and the members of each indexed by index_members (radiance_cache_impl.h) for
// add_cached_indirect to integrate.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/simd/target.h"
#include "render/cache/region_hemisphere.h"

PATINA_BEGIN_TARGET
namespace cache {

struct StoredHemispheres {
    // the hemispheres the item's regions reconstructed: by block, the indices in
    // PathScratch::cache_shared_hemispheres, and by pixel (RegionHemisphere::pixels)
    std::unordered_map<int64_t, std::vector<int32_t>> by_block;
    std::unordered_map<int64_t, int32_t> by_pixel;
    std::vector<const RegionHemisphere*> in_use;  // those the batch's members take
    std::vector<int32_t> slot;  // per PathScratch::cache_shared_hemispheres: its index in in_use, or -1
    std::vector<int32_t> first, members;          // in_use[s]'s members: [first[s], first[s + 1])
};

}  // namespace cache
PATINA_END_TARGET
