// The cache points of one batch, placed and built (place_cache_points, build_cache_points,
// radiance_cache_impl.h), and the queue of rays the reconstruction traces with them: the
// points the batch starts from, those it builds, each query's point, and the hemispheres of
// a chunk of queries as they are reconstructed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/simd/target.h"
#include "render/cache/cache_point.h"
#include "render/cache/ray_queue.h"
#include "render/integrators/integrator.h"

PATINA_BEGIN_TARGET
namespace cache {

struct CachePointBuild {
    std::vector<CachePoint> points;  // built by this call: [0, used)
    size_t used = 0;
    // the cache points a call starts from (the regions', PathScratch::cache_shared; none: null)
    const std::vector<const CachePoint*>* shared = nullptr;
    std::vector<const CachePoint*> pool;  // after placement: the shared points, then [0, used)
    std::vector<int32_t> pending;         // a round's queries that become new cache points
    std::vector<int32_t> assigned;        // per query: its cache point (in pool)
    std::vector<uint8_t> own;             // per query: it is its cache point's own query
    std::vector<int32_t> second;  // per query: the cache point that fills its holes (in pool), or -1
    RayQueue rays;                // the rays of a building chunk, of the holes of a chunk, of a split
    std::vector<PathResult> results;  // what the path tracer returned for them
    std::vector<float> textures;      // a chunk's reconstructed hemispheres: kChunk x R^2 x 3
    std::vector<float> luminances;    // bound_isolated_texels: one hemisphere's texels' luminance
};

}  // namespace cache
PATINA_END_TARGET
