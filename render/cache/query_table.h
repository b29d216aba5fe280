// The query table of one batch (docs/radiance-cache.md): the first-hit points the cache
// serves, at two levels of sharing. A *query* is one reconstructed hemisphere, shared by the
// pixels of a block whose points lie close; a *member* is one pixel's integration of it
// against its own BRDF and view, shared by that pixel's samples. Filled by collect_queries
// (cache_stages_impl.h), split by split_far_members and read by the reconstruction
// (radiance_cache_impl.h) and the integration of its hemispheres.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/simd/target.h"
#include "core/vec3.h"

PATINA_BEGIN_TARGET
namespace cache {

// A point that wants its hemisphere: where, its frame, its geometric normal, its path's key,
// and the least reuse radius a cache point made here gets (error_criterion.h).
struct Query {
    Vec3f p, ng, t, b, n;
    uint32_t key;
    float min_radius = 0;
};

struct QueryTable {
    std::vector<Query> queries;
    std::vector<int32_t> query_point;       // each query's shading point (its frame)
    std::vector<int32_t> member_point;      // each member's shading point (its view and BRDF)
    std::vector<int32_t> member_query;      // each member's query (-1 - s: the region's hemisphere stored[s])
    std::vector<Query> member_own;          // each member's own point, were it a query
    std::vector<int32_t> query_first, query_members;  // query u's members: [first[u], first[u + 1])
    std::vector<int32_t> member_of_point;   // each shading point's member (-1: none)
    std::unordered_map<int64_t, int32_t> pixel_member;  // by pixel_member_key: (pixel, hemisphere drawn)
    std::unordered_map<int64_t, std::vector<int32_t>> block_queries;  // a block's queries (of one material)
};

}  // namespace cache
PATINA_END_TARGET
