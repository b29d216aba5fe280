// `cache`'s light samples at the first hit: cache.light_samples of them a camera sample, each
// weighing 1 / light_samples, the BSDF-sampled half of the direct light (MIS) as `path`'s.
// Why: under an open sky the direct light at the camera's hit is most of the image's error
// and the cache does not touch it (cache-car, 192 x 128, 16 spp: 73 % of path's relMSE is
// the first vertex's direct light; `cache`, which takes path's one light sample there, kept
// 0.0050 of its 0.0061 on the floor alone); a shadow ray is cheap beside the cache's
// reconstruction, so more of them where the cache already spends pays there
// (docs/radiance-cache.md, "The car").
// The k-th sample of a camera sample of index i draws the numbers of index i * count + k:
// a pixel's count x spp light samples are one stratified set (the sampler's net), and with
// count 1 every number is the one `path` draws.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/integrators/integrator.h"
#include "render/integrators/light_samples_impl.h"

PATINA_BEGIN_TARGET
namespace render_detail {

// The first hits' light samples queued (the last one left for the bounce's
// resolve_shadow_rays, the others resolved here), the sample indices put back.
inline void queue_first_hit_light_samples(const Wavefront& wavefront) {
    const int count = wavefront.settings.cache.light_samples;
    if (count <= 1) {
        queue_light_samples(wavefront, 0);
        return;
    }
    PathScratch& scratch = wavefront.scratch;
    std::vector<int32_t>& index = scratch.point_index;
    scratch.own_point_index.assign(index.begin(), index.end());
    const float share = 1.0f / static_cast<float>(count);
    for (int k = count - 1; k >= 0; --k) {
        for (size_t q = 0; q < index.size(); ++q)
            index[q] = static_cast<int32_t>(static_cast<uint32_t>(scratch.own_point_index[q]) * count + k);
        queue_light_samples(wavefront, 0, share);
        if (k > 0) resolve_shadow_rays(wavefront);
    }
    index.swap(scratch.own_point_index);
}

}  // namespace render_detail
PATINA_END_TARGET
