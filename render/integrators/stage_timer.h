// Where a render's time goes: the wavefront integrator's stages, timed per thread.
//
// Each stage of a bounce (render/integrators/path_impl.h and its stage files) ends with one
// lap(): one steady_clock read per stage per bounce of a batch of thousands of paths, a few hundred nanoseconds against
// milliseconds of work, so the timers stay compiled in and always run. A thread's
// StageTimer lives in its PathScratch; the render job sums them over its workers
// (RenderJob::stage_times) and `patina bench --only profile` reports them
// (docs/performance.md).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <ctime>

namespace patina {

// The stages, in the order a bounce runs them. Trace* are ray traversal; Shade* the BRDF
// kernels; Light* light sampling; the rest is bookkeeping around them.
enum class Stage : int {
    CameraRays,       // camera rays generated, path state reset
    RayGather,        // the active paths' rays copied into the traced batch
    TraceCamera,      // traversal of camera rays (bounce 0)
    TraceSecondary,   // traversal of BRDF-sampled rays (bounces 1+)
    Emission,         // emitters hit, misses' environment and sun (with MIS weights)
    ShadingPoints,    // hits made shading points: interpolated normals, frames, AOVs
    GroupMaterial,    // shading points counting-sorted by material, local view directions, keys
    LightSelect,      // light-sample random numbers, each point's light picked, grouping by light
    LightSample,      // the light groups sampled N points at a time (gathers and scatters included)
    LightToLocal,     // light directions into the points' frames, side tests
    ShadeLight,       // BRDF value and pdf for the light samples (material kernels)
    ShadowQueue,      // MIS weights and contributions; shadow rays queued
    BsdfUniforms,     // BRDF-sampling random numbers
    ShadeSample,      // BRDF sampling: direction, pdf, value (material kernels)
    PathUpdate,       // throughput, Russian roulette, the next bounce's rays
    TraceShadow,      // traversal of shadow rays (any hit)
    ShadowResolve,    // unblocked shadow rays' light added to the paths
    // the radiance cache at the first hit (cache integrators, render/cache/; the cache's own
    // rays are traced by an inner path tracer whose time counts in the cache stage it serves)
    CachePlace,       // queries collected, cache points placed by the error criterion
    CacheBuild,       // cache points' hemispheres traced (R^2 rays each)
    CacheSurfels,     // layers, surfels, outlines and silhouettes of new cache points
    CacheReproject,   // cache points reprojected into the points that use them
    CacheHoles,       // what reprojection left traced from the points
    CacheIntegrate,   // reconstructed radiance integrated against the BRDF (or made a guide)
    CacheSplit,       // narrow lobes' first bounces split into several traced paths
    Count
};
constexpr int kStageCount = static_cast<int>(Stage::Count);

// Stable names (bench records, docs/performance.md), in Stage order.
inline const char* stage_name(Stage s) {
    static const char* const names[kStageCount] = {
        "camera_rays",   "ray_gather",    "trace_camera",  "trace_secondary", "emission",   "shading_points",
        "group_material", "light_select", "light_sample",  "light_to_local",  "shade_light", "shadow_queue",
        "bsdf_uniforms", "shade_sample",  "path_update",   "trace_shadow",    "shadow_resolve",
        "cache_place",   "cache_build",   "cache_surfels", "cache_reproject", "cache_holes", "cache_integrate",
        "cache_split"};
    return names[static_cast<int>(s)];
}

// Accumulated nanoseconds per stage, and the work they did.
struct StageTimes {
    int64_t ns[kStageCount] = {};
    uint64_t camera_rays = 0, secondary_rays = 0, shadow_rays = 0, shading_points = 0;
    // a render job's threads' time in their work items: the stages above plus the pixel
    // sampler and film between batches (set by RenderJob, not by the timer)
    int64_t item_ns = 0;

    StageTimes& operator+=(const StageTimes& o) {
        for (int k = 0; k < kStageCount; ++k) ns[k] += o.ns[k];
        camera_rays += o.camera_rays;
        secondary_rays += o.secondary_rays;
        shadow_rays += o.shadow_rays;
        shading_points += o.shading_points;
        item_ns += o.item_ns;
        return *this;
    }
};

// One thread's clock: start() at the entry of a traced batch, lap(stage) as each stage ends
// (the time since the previous lap or start is that stage's). Wall time by default; with
// use_cpu_time(true), the thread's CPU time, which leaves out the time the thread waits
// for a core: the breakdown of a loaded machine (docs/performance.md), at the price of a
// system call a lap (about a microsecond, some 2 % of a render).
class StageTimer {
public:
    void use_cpu_time(bool on) { m_cpu = on; }
    bool uses_cpu_time() const { return m_cpu; }
    void start() { m_last = now(); }
    void lap(Stage s) {
        const int64_t t = now();
        times.ns[static_cast<int>(s)] += t - m_last;
        m_last = t;
    }
    // nanoseconds on the clock in use (item times use it too, so the stages add up)
    int64_t now() const {
        if (m_cpu) {
            timespec ts;
            clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
            return static_cast<int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
        }
        return std::chrono::duration_cast<std::chrono::nanoseconds>(
                   std::chrono::steady_clock::now().time_since_epoch()).count();
    }
    StageTimes times;

private:
    int64_t m_last = 0;
    bool m_cpu = false;
};

}  // namespace patina
