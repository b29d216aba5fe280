// A reconstructed hemisphere kept by an image region (render/cache/cache_regions.h;
// docs/radiance-cache.md, "Reconstructions kept by the regions"): the incident indirect
// radiance a query of the region's pre-pass reprojected from its cache point and completed
// by tracing its holes, in the query's frame. The work items' first-hit points that would
// have made the same query (the same block of pixels, sharing the query's surface, within
// its reach) integrate it against their own BRDFs instead of reconstructing it again, so
// every pass of a tile (and every tile of a region) shares one reconstruction per block
// surface and more samples a pixel cost mainly their direct light.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/vec3.h"

namespace patina {

struct RegionHemisphere {
    int64_t block = 0;      // the block of pixels (cache.block a side, image-aligned) of its query
    int32_t region = 0;     // the region that made it (only its own pixels take it)
    int32_t material = 0;   // the query's material (a member of another one never shares it)
    Vec3f p, n;             // the query's point and shading normal (what a member shares with)
    Vec3f t, b;             // with n the hemisphere's frame
    float reach = 0;        // a member farther from p takes a reconstruction of its own
    std::vector<float> radiance;  // R^2 x RGB, texel j * R + i of the frame
    // the pixels (y * width + x) whose pre-pass point (in the pixel: render/cache/cache_generations.h) took it: a
    // sample of such a pixel on the same surface takes it whatever its distance from p
    std::vector<int64_t> pixels;
};

inline size_t region_hemisphere_bytes(const RegionHemisphere& h) {
    return sizeof(RegionHemisphere) + sizeof(float) * h.radiance.capacity() + sizeof(int64_t) * h.pixels.capacity();
}

}  // namespace patina
