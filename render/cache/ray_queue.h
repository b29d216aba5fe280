// Rays for the path tracer: origins, directions, the stream key and index of each (a
// hemisphere's texels are one stream, the texel its index: with the Sobol sampler the paths
// of a hemisphere are one stratified sequence). Filled by the cache's building, hole tracing
// and splits (radiance_cache_impl.h, cache_stages_impl.h), traced by trace_queue.
#pragma once

#include <cstdint>
#include <vector>

#include "core/simd/target.h"
#include "core/vec3.h"

PATINA_BEGIN_TARGET
namespace cache {

struct RayQueue {
    std::vector<float> org, dir;
    std::vector<uint32_t> keys, indices;
    std::vector<int32_t> where;  // the caller's index of each ray (a texel)
    void clear() {
        org.clear(), dir.clear(), keys.clear(), indices.clear(), where.clear();
    }
    void push(const Vec3f& o, const Vec3f& d, uint32_t key, uint32_t index, int32_t at) {
        // push_back, not insert of an initializer list: the insert called memmove for three
        // floats, 0.5 % of the room's render (docs/radiance-cache.md, "The cache's own stages cheaper")
        org.push_back(o.x), org.push_back(o.y), org.push_back(o.z);
        dir.push_back(d.x), dir.push_back(d.y), dir.push_back(d.z);
        keys.push_back(key);
        indices.push_back(index);
        where.push_back(at);
    }
    size_t size() const { return keys.size(); }
};

}  // namespace cache
PATINA_END_TARGET
