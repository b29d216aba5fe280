// The path integrator's interface: radiance for a batch of camera samples.
//
// A pixel sampler (render_job.cpp's uniform sampler now, the adaptive antialiasing
// later) decides where in which pixel to shoot; the integrator returns each sample's
// radiance and first-hit AOVs; the sampler filters them into pixels. The batch is traced
// as a wavefront: all paths of a bounce are traced in packets of N rays, their shading
// points grouped by material and shaded N at a time (one light sample each, the shadow
// rays traced as packets, SIMD BRDF evaluation, MIS between light and BRDF sampling).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/vec3.h"
#include "render/cache/cache_point.h"
#include "render/cache/cache_probe.h"
#include "render/cache/cache_settings.h"
#include "render/cache/region_hemisphere.h"
#include "render/integrators/stage_timer.h"
#include "render/lights/grid2.h"
#include "render/scene.h"

namespace patina {

namespace guiding {
class GuideField;
struct GuideRecordSink;
}  // namespace guiding

// Where the paths' random numbers come from (render/samplers/sample_numbers.h): Owen-scrambled
// Sobol points, one sequence a pixel, or independent hashes of (path, dimension).
enum class SamplerKind : uint8_t { Sobol, Independent };

struct CameraSample {
    float film_x, film_y;  // film position in pixels (x right, y down)
    uint32_t key;    // the key of the path's stream, a pixel's sequence (render/samplers/rng.h stream_key)
    uint32_t index;  // the path's sample in that stream
};

struct PathResult {
    float rgb[3];       // radiance along the camera ray, W/(m^2 sr)
    float albedo[3];    // first hit: the material's albedo estimate (0 on a miss)
    float normal[3];    // first hit: shading normal, world space (0 on a miss)
    float depth;        // first hit: distance from the camera (inf on a miss)
    float illuminance;  // first hit: illuminance on the shading normal, lux (683 lm/W x Y): direct, plus
                        // the light reflected by the scene with IntegratorSettings::indirect_illuminance
    int32_t material;   // first hit: its material (-1 on a miss; the radiance cache's glossy hits)
};

// path: the unidirectional path tracer. cache: direct light as the path tracer takes it, the
// indirect light at the first hit from the radiance cache's reconstructed incident radiance
// integrated against the BRDF (biased; docs/radiance-cache.md). cache-guided: the path
// tracer with the first bounce drawn from the cache's radiance x BRDF and from the BRDF,
// combined by MIS (unbiased).
enum class IntegratorMode : int { Path = 0, Cache = 1, CacheGuided = 2 };

// The kernels count a path's vertices, where the scene file's (and RenderOptions') max_depth
// counts its segments, Mitsuba 3's convention (2: direct light): this is the one place where
// one becomes the other. Max_depth 1 (emitters seen directly) renders as 2 does.
inline int path_vertices(int max_depth) { return max_depth > 1 ? max_depth - 1 : 1; }

struct IntegratorSettings {
    int max_depth = 8;  // path vertices (path_vertices of the scene's max_depth); 1: direct lighting only
    int rr_depth = 3;   // Russian roulette from this bounce on
    // The illuminance AOV also counts light reflected by the scene: from each first hit, one
    // cosine-weighted sensor ray continued as a path of at most max_depth - 1 further
    // vertices (sensor_illuminance_indirect's estimate). Off: the AOV is direct only, and
    // the image is the same bits either way (the sensor paths draw their own numbers).
    bool indirect_illuminance = false;
    SamplerKind sampler = SamplerKind::Sobol;
    IntegratorMode mode = IntegratorMode::Path;
    CacheSettings cache;
    // the render's passes: with more than one, `cache`'s regions reconstruct hemispheres that
    // serve them all (render/cache/region_hemisphere.h)
    int passes = 1;
};

// A shading point of the current bounce.
struct ShadingPoint {
    int32_t path;
    int32_t material;
    Vec3f p, ng;     // position, geometric normal (towards the viewer)
    Vec3f t, b, n;   // shading frame: tangent, bitangent, normal
    float eta;       // dielectrics: index beyond the surface / index on the viewer's side
};

// The sorted shading points' fields again as (n, 3) rows and (n,) lanes: what the N-wide
// stages load.
struct ShadingPointLanes {
    std::vector<float> position, geometric_normal, tangent, bitangent, normal;
    std::vector<int32_t> path;  // the path each point is on
};

// One light sample per shading point (render/lights/sampling_impl.h): the unit direction
// from the point, the RGB it brings (radiance, or intensity / dist^2 for a delta light), the
// distance to the light point (inf at infinity), the pdf (selection included), whether the
// light is a delta light (no MIS), and whether the sample is usable (pdf > 0 and finite).
struct LightSampleQueue {
    std::vector<float> dir, rgb, dist, pdf;
    std::vector<uint8_t> delta, usable;
};

// The bounce's shadow rays (render/integrators/shadow_rays_impl.h): origin, unit direction
// and length, the RGB and the lux their light adds to path `path` when not `blocked`.
struct ShadowRayQueue {
    std::vector<float> org, dir, tmax, rgb, lux;
    std::vector<int32_t> path;
    std::vector<uint8_t> blocked;
};

// Work arrays a thread reuses from batch to batch.
struct PathScratch {
    // per path
    std::vector<float> org, dir, throughput, prev_pdf, prev_pos;
    std::vector<int32_t> active, next_active;
    // per traced ray of a bounce (rays_gathered: ray_org and ray_dir hold the active paths'
    // rays in order already), and the next bounce's rays as the paths that go on leave
    std::vector<float> ray_org, ray_dir, hit_t, hit_u, hit_v, next_ray_org, next_ray_dir;
    bool rays_gathered = false;
    std::vector<int32_t> hit_prim;
    // per shading point, grouped by material
    std::vector<ShadingPoint> sorted;
    std::vector<int32_t> material_start;
    std::vector<int32_t> shade_hits;  // the bounce's hits that may become shading points, in hit order
    ShadingPointLanes point_lanes;
    std::vector<float> material_eta, material_transmissive, material_two_sided;  // per material, for gathers
    // per point: view and next direction (local), BSDF value and density, eta; the uniforms a light or
    // BSDF sample draws (the light or lobe pick, then the direction's u and v)
    std::vector<float> v_local, l_local, bsdf_rgb, pdf, eta, u_pick, uniform_u, uniform_v;
    std::vector<int32_t> point_keys, point_index;  // the paths' stream keys and sample indices (uint32 bits)
    std::vector<int32_t> own_point_index;          // point_index kept while first-hit light samples draw theirs
    SamplerKind sampler = SamplerKind::Sobol;      // what the point_keys and point_index draw from
    // misses (the environment seen), and the points that sample the environment
    std::vector<int32_t> misses;
    std::vector<float> miss_dir, miss_rgb, miss_pdf;
    // the points grouped by the light they chose, and one group's inputs and results
    std::vector<int32_t> light_of_point, light_start, light_fill, light_points;
    std::vector<float> group_pos, group_u1, group_u2, group_dir, group_rgb, group_dist, group_pdf, group_sel;
    std::vector<float> point_sel;  // each point's probability of its light
    std::vector<float> selection_pos, selection_weights;  // the points' positions; their lights' weights
    LightSampleQueue light_samples;
    ShadowRayQueue shadow_rays;
    // sensor paths (indirect illuminance): their sensors, keys and results
    std::vector<ShadingPoint> sensors;
    std::vector<CameraSample> sensor_samples;
    std::vector<PathResult> sensor_results;
    size_t rays_traced = 0;  // primary, secondary and shadow rays since construction
    StageTimer timer;        // time per integrator stage since construction (render/integrators/stage_timer.h)
    // the radiance cache (render/cache/radiance_cache_impl.h): per path, whether its first
    // hit's indirect light came from the cache (it then only looks for emission)
    std::vector<uint8_t> cached;
    // the cache's work memory (render/cache/cache_state_impl.h, CacheState), made by the kernels
    // of width cache_width (no make_shared: its tag object is one the width-16 units may not
    // define, see CMakeLists.txt)
    std::unique_ptr<void, void (*)(void*)> cache{nullptr, nullptr};
    int cache_width = 0;
    // the cache points the batch's cache starts from: those of the regions its tile overlaps
    // (render/cache/cache_regions.h; set by the render job for each work item, held by it)
    std::vector<const CachePoint*> cache_shared;
    // ...and the reconstructed hemispheres those regions keep (render/cache/region_hemisphere.h)
    std::vector<const RegionHemisphere*> cache_shared_hemispheres;
    // cache-guided's trained guide (render/guiding/): the field the bounces draw from (null:
    // none), and during a training pass the sink its path vertices' records go to
    const guiding::GuideField* guide_field = nullptr;
    guiding::GuideRecordSink* guide_sink = nullptr;
    // the cache's statistics since construction
    size_t cache_points = 0, cache_queries = 0, cache_texels_reprojected = 0, cache_texels_traced = 0;
};

struct RenderKernels {
    int width;
    void (*trace_paths)(const RenderScene& scene, const IntegratorSettings& settings, const CameraSample* samples,
                        size_t n, PathResult* out, PathScratch& scratch);
    // lux[i] = direct illuminance (lux) on a sensor at points[i] facing unit normals[i], the
    // mean of `samples` light samples (each shadowed, each sensor its own), for sensors [begin, end)
    void (*sensor_illuminance)(const RenderScene& scene, const float* points, const float* normals, size_t begin,
                               size_t end, int samples, uint32_t seed, float* lux, PathScratch& scratch);
    // lux[i] += the illuminance (lux) that light reflected by the scene adds on the sensor at
    // points[i] facing normals[i], for sensors [begin, end): the mean of `samples` sensor
    // rays over the cosine-weighted hemisphere, each continued as a path of at most
    // settings.max_depth vertices whose first hit's emission is not counted (light sampling
    // counts that: sensor_illuminance). Keys from (seed, sensor, sample) as there, salted.
    void (*sensor_illuminance_indirect)(const RenderScene& scene, const IntegratorSettings& settings,
                                        const float* points, const float* normals, size_t begin, size_t end,
                                        int samples, uint32_t seed, float* lux, PathScratch& scratch);
    // out[i] = the 2-D table at (x[i], y[i]), bilinear, clamped to the axes
    void (*grid2_eval)(const Grid2View& grid, const float* x, const float* y, float* out, size_t n);
    // The light selection at points[q], q < n: the probability that a shading point there picks
    // light k (the environment last; count = scene.selection.size()) as light sampling's pick
    // computes it, into pick[q * count + k], and as an MIS weight does, into mis
    void (*light_selection)(const RenderScene& scene, const float* points, size_t n, float* pick, float* mis);
    // The radiance cache at point a (unit normal na) reprojected into point b (normal nb),
    // with the settings' cache parameters and depth (render/cache/cache_probe.h)
    void (*cache_probe)(const RenderScene& scene, const IntegratorSettings& settings, const float* a, const float* na,
                        const float* b, const float* nb, uint32_t seed, bool unknown_masks, CacheProbe& out);
    // The radiance cache's points for an image region (render/cache/cache_regions.h): the
    // region's pre-pass camera samples traced to their first hits, the cache points placed
    // there as a work item places them (settings' mode and cache parameters) and built;
    // for `cache`, the hemispheres of the pre-pass's queries reconstructed and kept too
    void (*build_cache_region)(const RenderScene& scene, const IntegratorSettings& settings,
                               const CameraSample* samples, size_t n, std::vector<CachePoint>& points,
                               std::vector<RegionHemisphere>& hemispheres, PathScratch& scratch);
    // samples[q].film_x and .film_y (the pixel's corner) plus the sample's pixel-x and pixel-y numbers
    // (render/samplers/sample_numbers.h, from its key and index), q < n: the uniform sampler's jittered
    // positions, N samples at a time (a Sobol number is 13 hashes: too dear one at a time)
    void (*jitter_pixel_positions)(SamplerKind kind, CameraSample* samples, size_t n);
    // Radiance-cache points at sensors [begin, end) (render/cache/sensor_cache_points_impl.h):
    // lux[i] the indirect illuminance of an R x R hemisphere (R = resolution) of jittered texel
    // rays from points[i] about normals[i], traced as sensor_illuminance_indirect's paths, and
    // harmonic_distance[i] the texels' harmonic mean hit distance (inf: none hit)
    void (*sensor_cache_points)(const RenderScene& scene, const IntegratorSettings& settings, const float* points,
                                const float* normals, size_t begin, size_t end, int resolution, uint32_t seed,
                                float* lux, float* harmonic_distance, PathScratch& scratch);
};

const RenderKernels& render_kernels_w1();
const RenderKernels& render_kernels_w4();
const RenderKernels& render_kernels_w8();
const RenderKernels& render_kernels_w16();
const RenderKernels& render_kernels_for(int width);  // 0 = default; throws std::invalid_argument

}  // namespace patina
