// The radiance cache's biased integrator (integrator `cache`; thesis chapter 4,
// docs/radiance-cache.md): the path tracer's stages, with the indirect light at the first hit
// taken from the cache -- the incident radiance reconstructed from nearby cache points
// (reprojected, holes traced) integrated against the BSDF -- after which a path only looks for
// the emission it sees. Also the image regions' cache points, built before the passes.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/simd/kernel_width.h"
#include "render/cache/cache_point.h"
#include "render/cache/cache_stages_impl.h"
#include "render/cache/region_hemisphere.h"
#include "render/integrators/bsdf_samples_impl.h"
#include "render/integrators/emission_impl.h"
#include "render/integrators/first_hit_light_samples_impl.h"
#include "render/integrators/integrator.h"
#include "render/integrators/light_samples_impl.h"
#include "render/integrators/shading_points_impl.h"
#include "render/integrators/wavefront_impl.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// The radiance cache's rays (origins, directions, stream keys and indices; n of them)
// traced by the path tracer with `settings` (mode path), leaving out the emission they see
// directly: out[i].rgb is the indirect radiance arriving along ray i, depth and normal
// what it hit first (kernels_impl.h).
void trace_given_rays(const RenderScene& scene, const IntegratorSettings& settings, const float* org, const float* dir,
                      const uint32_t* keys, const uint32_t* indices, size_t n, PathResult* out, PathScratch& scratch,
                      std::vector<CameraSample>& samples);

// The settings of the cache's own rays, which start at the first hit: one bounce fewer,
// roulette one sooner.
inline IntegratorSettings cache_ray_settings(const IntegratorSettings& settings) {
    IntegratorSettings inner = settings;
    inner.mode = IntegratorMode::Path;
    inner.indirect_illuminance = false;
    inner.max_depth = settings.max_depth - 1;
    inner.rr_depth = std::max(1, settings.rr_depth - 1);
    // a guide needs the shape of the indirect light, not its value: the direct light at the
    // hits (one bounce) is that shape at a fraction of the full paths' cost
    if (settings.mode == IntegratorMode::CacheGuided) inner.max_depth = 1;
    return inner;
}

// What traces the cache's rays for the batch of `wavefront` (its cache state's own scratch): the
// path tracer with cache_ray_settings.
struct CacheRayTracer {
    const RenderScene& scene;
    const IntegratorSettings inner;
    cache::CacheState& state;
    CacheRayTracer(const RenderScene& scene, const IntegratorSettings& settings, PathScratch& scratch)
        : scene(scene), inner(cache_ray_settings(settings)), state(cache::cache_state(scratch)) {}
    void operator()(const float* o, const float* d, const uint32_t* k, const uint32_t* idx, size_t m,
                    PathResult* r) const {
        trace_given_rays(scene, inner, o, d, k, idx, m, r, state.inner, state.inner_samples);
    }
};

// Whether the cache serves the first hits: there is indirect light to serve.
inline bool cache_serves(const Wavefront& wavefront) { return wavefront.settings.max_depth > 1; }

// The bounces of `cache`'s camera paths: path_bounces' stages, and at the first hit the
// cache's indirect light (the served paths marked in wavefront.scratch.cached: may_shade ends them there).
inline void cache_bounces(const Wavefront& wavefront) {
    wavefront.scratch.sampler = wavefront.settings.sampler;  // what fill_uniforms draws the points' numbers from
    for (int depth = 0; !wavefront.scratch.active.empty(); ++depth) {
        const HitBatch hits = trace_bounce(wavefront, depth);
        add_emission_and_environment(wavefront, hits, depth);
        make_shading_points(wavefront, hits, depth);
        if (depth == 0 && cache_serves(wavefront)) {  // the first hits' indirect light: reprojected, holes traced
            CacheRayTracer tracer(wavefront.scene, wavefront.settings, wavefront.scratch);
            cache::add_cached_indirect(wavefront, tracer);
        }
        if (depth == 0) queue_first_hit_light_samples(wavefront);
        else queue_light_samples(wavefront, depth);
        sample_bsdf(wavefront, depth);
        resolve_shadow_rays(wavefront);
        next_bounce(wavefront);
    }
}

// `cache` for a batch of camera samples.
inline void trace_cache(const Wavefront& wavefront, size_t n) {
    start_camera_paths(wavefront, n);
    wavefront.scratch.cached.assign(n, 0);  // none served by the cache yet
    wavefront.scratch.timer.lap(Stage::CameraRays);
    cache_bounces(wavefront);
}

// An image region's cache points (integrator.h, build_cache_region): the camera rays' first
// hits, then the cache's placement and building there (render/cache/cache_stages_impl.h).
void build_cache_region(const RenderScene& scene, const IntegratorSettings& settings,
                        const CameraSample* camera_samples, size_t n, std::vector<CachePoint>& points,
                        std::vector<RegionHemisphere>& hemispheres, PathScratch& scratch) {
    enter_kernel();
    std::vector<PathResult> out(n);
    const Wavefront wavefront{scene,   settings,           camera_samples,       out.data(),
                      scratch, lights_emit(scene), scene_has_sun(scene), scene.ray_offset};
    scratch.sensors.clear();
    scratch.timer.start();
    start_camera_paths(wavefront, n);
    if (settings.mode == IntegratorMode::Cache) scratch.cached.assign(n, 0);
    scratch.timer.lap(Stage::CameraRays);
    const HitBatch hits = trace_bounce(wavefront, 0);
    make_shading_points(wavefront, hits, 0);
    scratch.sensors.clear();
    CacheRayTracer tracer(scene, settings, scratch);
    cache::build_region_points(wavefront, tracer, points, hemispheres);
    scratch.active.clear();
}

}  // namespace render_detail
PATINA_END_TARGET
