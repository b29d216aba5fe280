// The integrators' kernels at one width (integrator.h's RenderKernels), compiled once per width
// by integrator_w{1,4,8,16}.cpp. Each integrator is a stage list in its own file:
//   path_impl.h          path (and direct, at max_depth 1): the path tracer
//   cache_impl.h         cache: the path tracer with the first hit's indirect light from the radiance cache
//   cache_guided_impl.h  cache-guided: the path tracer with the first bounces guided by the cache
//   sensors_impl.h       illuminance sensors: direct by light sampling, indirect by sensor paths
//   (render/cache/sensor_cache_points_impl.h: radiance-cache points at sensors, for their indirect light)
// over the shared stages (wavefront_impl.h, emission_impl.h, shading_points_impl.h,
// light_samples_impl.h, bsdf_samples_impl.h). Everything random comes from
// render/samplers/sample_numbers.h (Sobol or rng.h's counter-based hash, both integer functions
// of the path's stream and sample), and every kernel gives the same bits at every width, so one
// seed renders the same image at widths 1, 4, 8 and 16 (the tests check this).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/simd/kernel_width.h"
#include "render/cache/sensor_cache_points_impl.h"
#include "render/integrators/cache_guided_impl.h"
#include "render/integrators/cache_impl.h"
#include "render/integrators/cache_probe_impl.h"
#include "render/integrators/integrator.h"
#include "render/integrators/path_impl.h"
#include "render/integrators/sensors_impl.h"
#include "render/integrators/wavefront_impl.h"
#include "render/samplers/sample_numbers.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// Radiance and first-hit AOVs for a batch of camera samples, by the settings' integrator.
void trace_paths(const RenderScene& scene, const IntegratorSettings& settings, const CameraSample* camera_samples,
                 size_t n, PathResult* out, PathScratch& scratch) {
    enter_kernel();
    const Wavefront wavefront{scene,   settings,           camera_samples,       out,
                      scratch, lights_emit(scene), scene_has_sun(scene), scene.ray_offset};
    scratch.sensors.clear();
    scratch.timer.start();
    switch (settings.mode) {
        case IntegratorMode::Path: trace_path(wavefront, n); break;
        case IntegratorMode::Cache: trace_cache(wavefront, n); break;
        case IntegratorMode::CacheGuided: trace_cache_guided(wavefront, n); break;
    }
    add_indirect_illuminance(scene, settings, camera_samples, out, scratch);
}

void trace_given_rays(const RenderScene& scene, const IntegratorSettings& settings, const float* org, const float* dir,
                      const uint32_t* keys, const uint32_t* indices, size_t n, PathResult* out, PathScratch& scratch,
                      std::vector<CameraSample>& samples) {
    samples.resize(n);
    for (size_t i = 0; i < n; ++i) samples[i] = CameraSample{0.0f, 0.0f, keys[i], indices[i]};
    Wavefront wavefront{scene,   settings,           samples.data(),       out,
                scratch, lights_emit(scene), scene_has_sun(scene), scene.ray_offset};
    wavefront.first_emission = false;
    start_given_paths(wavefront, org, dir, n);
    path_bounces(wavefront);
}

// The uniform sampler's jitter (render/integrators/integrator.h, jitter_pixel_positions): pixel-x and pixel-y
// numbers of N samples at a time, each lane the bits sample_uniform gives it.
void jitter_pixel_positions(SamplerKind kind, CameraSample* camera_samples, size_t n) {
    enter_kernel();
    for_blocks(n, [&](size_t i, int lanes) {
        alignas(64) int32_t key[N] = {}, index[N] = {};
        alignas(64) float fx[N] = {}, fy[N] = {};
        uint32_t all = 0;
        for (int k = 0; k < lanes; ++k) {
            const CameraSample& c = camera_samples[i + k];
            key[k] = static_cast<int32_t>(c.key);
            index[k] = static_cast<int32_t>(c.index);
            fx[k] = c.film_x;
            fy[k] = c.film_y;
            all |= c.index;
        }
        const I keys = load_n<N>(key), indices = load_n<N>(index);
        const int bits = bit_length(all);
        store_n<N>(fx, load_n<N>(fx) + sample_uniform_lanes(kind, keys, indices, bits, 0, kDimPixelX));
        store_n<N>(fy, load_n<N>(fy) + sample_uniform_lanes(kind, keys, indices, bits, 0, kDimPixelY));
        for (int k = 0; k < lanes; ++k) {
            camera_samples[i + k].film_x = fx[k];
            camera_samples[i + k].film_y = fy[k];
        }
    });
}

}  // namespace render_detail
PATINA_END_TARGET
