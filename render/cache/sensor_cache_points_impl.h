// Radiance-cache points at illuminance sensors (issue 32; docs/lighting.md, "Indirect
// illuminance from the radiance cache"): a sensor is a point with a normal and a cosine
// response, so a cache point built at it is the cache's own hemisphere -- R x R equal-area
// texels (hemisphere.h), one jittered ray each (jittered_direction, the stream a cache point's),
// traced as one wavefront by the path tracer with the emission seen directly left out -- and
// what the sensor reads from it is that hemisphere integrated against its cosine:
//     E = 683 lm/W x sum over texels of Y(L_t) cos(theta_t) x 2 pi / R^2,
// the texels' equal solid angle making the integral a plain sum. The harmonic mean of the
// texels' first-hit distances is the cache point's reuse radius in the error criterion
// (error_criterion.h), by which the sensors between cache points gather from them
// (python/patina/lighting/indirect_cache.py).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/constants.h"
#include "core/simd/kernel_width.h"
#include "render/cache/hemisphere.h"
#include "render/cache/radiance_cache_impl.h"
#include "render/integrators/cache_impl.h"
#include "render/integrators/sensors_impl.h"

PATINA_BEGIN_TARGET
namespace render_detail {

// Points [begin, end): lux[i] the indirect illuminance of cache point i's hemisphere, and
// harmonic_distance[i] its texels' harmonic mean hit distance (inf when none hit). Keys from
// (seed, point) as sensor_illuminance's, salted as a cache point's.
void sensor_cache_points(const RenderScene& scene, const IntegratorSettings& settings, const float* points,
                         const float* normals, size_t begin, size_t end, int resolution, uint32_t seed, float* lux,
                         float* harmonic_distance, PathScratch& scratch) {
    enter_kernel();
    const size_t texels = static_cast<size_t>(resolution) * resolution;
    const float texel_lux = kLumensPerWatt * cache::texel_solid_angle(resolution);
    IntegratorSettings inner = settings;
    inner.mode = IntegratorMode::Path;  // the hemisphere's rays are plain paths from the sensor
    inner.indirect_illuminance = false;
    cache::RayQueue rays;
    std::vector<PathResult> results;
    std::vector<CameraSample> samples;
    std::vector<float> cosines;
    const size_t per_wavefront = std::max<size_t>(1, cache::kMaxWavefront / texels);
    for (size_t first = begin; first < end; first += per_wavefront) {
        const size_t last = std::min(end, first + per_wavefront);
        rays.clear();
        cosines.clear();
        for (size_t i = first; i < last; ++i) {
            const ShadingPoint sp = sensor_point(points, normals, i, i - first);
            const cache::Query q{sp.p, sp.ng, sp.t, sp.b, sp.n, cache::cache_point_key(stream_key(seed, uint32_t(i)))};
            for (size_t t = 0; t < texels; ++t) {
                const Vec3f d = cache::jittered_direction(q, resolution, static_cast<int32_t>(t), q.key);
                rays.push(sp.p + scene.ray_offset * sp.ng, d, q.key, static_cast<uint32_t>(t), static_cast<int32_t>(i));
                cosines.push_back(std::max(0.0f, dot(d, sp.n)));
            }
        }
        results.resize(rays.size());
        trace_given_rays(scene, inner, rays.org.data(), rays.dir.data(), rays.keys.data(), rays.indices.data(),
                         rays.size(), results.data(), scratch, samples);
        for (size_t i = first; i < last; ++i) {
            double sum = 0, inverse_distances = 0;
            for (size_t t = 0; t < texels; ++t) {
                const size_t r = (i - first) * texels + t;
                sum += double(luminance(results[r].rgb)) * cosines[r];
                const float depth = results[r].depth;
                if (std::isfinite(depth) && depth > 0) inverse_distances += 1.0 / depth;
            }
            lux[i] = static_cast<float>(sum * texel_lux);
            harmonic_distance[i] = inverse_distances > 0 ? static_cast<float>(texels / inverse_distances) : kInfinity;
        }
    }
}

}  // namespace render_detail
PATINA_END_TARGET
