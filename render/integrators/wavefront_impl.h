// The wavefront's state and its first and last steps (the integrators in path_impl.h,
// cache_impl.h and cache_guided_impl.h are stage lists over it): a batch of paths, each with
// its ray, throughput and the density its last BSDF sample had; started from camera samples
// or given rays; each bounce's rays traced together, N per packet.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "core/simd/kernel_width.h"
#include "core/vec3.h"
#include "render/accel/trace_kernels.h"
#include "render/cache/cache_stages_impl.h"
#include "render/camera/camera.h"
#include "render/integrators/integrator.h"
#include "render/integrators/shadow_rays_impl.h"
#include "render/lights/sampling_impl.h"
#include "render/samplers/sample_numbers.h"
#include "render/scene.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// A world direction in a shading point's frame, and back.
inline Vec3f to_local(const ShadingPoint& sp, const Vec3f& d) { return {dot(d, sp.t), dot(d, sp.b), dot(d, sp.n)}; }
inline Vec3f to_world(const ShadingPoint& sp, const Vec3f& l) { return l.x * sp.t + l.y * sp.b + l.z * sp.n; }

// What every stage of one trace_paths call works on: the scene, the batch's camera samples
// and results, and the paths' state in the scratch arrays -- per path its ray (org, dir),
// throughput, and where and with what density its last BRDF sample left (prev_pos,
// prev_pdf; 0 for a camera ray), which the MIS weights of emission need.
struct Wavefront {
    const RenderScene& scene;
    const IntegratorSettings& settings;
    const CameraSample* camera_samples;  // one per path
    PathResult* results;                 // one per path
    PathScratch& scratch;
    bool can_sample_lights;  // some light (or the environment) can light something
    bool has_sun;
    float ray_offset;        // secondary rays leave this far off the surface
    // emission the first segment sees counts; not for sensor paths, whose direct light
    // light sampling counts (sensor_illuminance)
    bool first_emission = true;
};

// Path i starts along (o, d) with throughput 1 (its result emptied first by start_paths).
inline void start_path(const Wavefront& wavefront, size_t i, const Vec3f& o, const Vec3f& d) {
    PathScratch& scratch = wavefront.scratch;
    store_vec3(o, scratch.org.data() + 3 * i);
    store_vec3(d, scratch.dir.data() + 3 * i);
    std::fill(scratch.throughput.data() + 3 * i, scratch.throughput.data() + 3 * i + 3, 1.0f);
    scratch.prev_pdf[i] = 0;  // a first segment: whatever it sees counts in full
    scratch.active.push_back(static_cast<int32_t>(i));
}

// The path arrays sized for n paths, none active yet, the n results empty.
inline void start_paths(const Wavefront& wavefront, size_t n) {
    PathScratch& scratch = wavefront.scratch;
    grow(scratch.org, 3 * n);
    grow(scratch.dir, 3 * n);
    grow(scratch.throughput, 3 * n);
    grow(scratch.prev_pdf, n);
    grow(scratch.prev_pos, 3 * n);
    scratch.active.clear();
    scratch.rays_gathered = false;
    scratch.cached.clear();  // none served by the radiance cache (start_camera_paths says otherwise)
    if (scratch.cache) cache::cache_state(scratch).guides.clear();  // no guides until place_guide_points
    for (size_t i = 0; i < n; ++i) {
        PathResult& r = wavefront.results[i];
        std::fill(r.rgb, r.rgb + 3, 0.0f);
        std::fill(r.albedo, r.albedo + 3, 0.0f);
        std::fill(r.normal, r.normal + 3, 0.0f);
        r.depth = kInfinity;
        r.illuminance = 0;
        r.material = -1;
    }
}

// A pinhole camera's rays through the film positions of samples [0, n), N at a time:
// camera_ray's operations lane by lane (the same bits), from the camera's position.
inline void pinhole_rays(const Camera& c, const CameraSample* camera_samples, size_t n, float* org, float* dir) {
    const float aspect = static_cast<float>(c.width) / static_cast<float>(c.height);
    const V3 right{F(c.right[0]), F(c.right[1]), F(c.right[2])}, up{F(c.up[0]), F(c.up[1]), F(c.up[2])};
    const V3 forward{F(c.forward[0]), F(c.forward[1]), F(c.forward[2])};
    const V3 o{F(c.position[0]), F(c.position[1]), F(c.position[2])};
    for_blocks(n, [&](size_t i, int lanes) {
        alignas(64) float fx[N] = {}, fy[N] = {};
        for (int k = 0; k < lanes; ++k) {
            fx[k] = camera_samples[i + k].film_x;
            fy[k] = camera_samples[i + k].film_y;
        }
        const F sx = (F(2.0f) * load_n<N>(fx) / F(static_cast<float>(c.width)) - F(1.0f)) * F(c.tan_half_fov) *
                     F(aspect);
        const F sy = (F(1.0f) - F(2.0f) * load_n<N>(fy) / F(static_cast<float>(c.height))) * F(c.tan_half_fov);
        const V3 d = forward + sx * right + sy * up;
        const F inv = F(1.0f) / sqrt_exact(dot(d, d));
        store_rows(org, i, lanes, o);
        store_rows(dir, i, lanes, inv * d);
    });
}

// The batch's camera rays, with throughput 1 and empty results; every path active.
inline void start_camera_paths(const Wavefront& wavefront, size_t n) {
    start_paths(wavefront, n);
    const bool lens = wavefront.scene.camera.aperture_radius > 0;  // a pinhole draws no lens numbers
    if (!lens) {  // start_path for every path, the rays N at a time
        PathScratch& scratch = wavefront.scratch;
        pinhole_rays(wavefront.scene.camera, wavefront.camera_samples, n, scratch.org.data(), scratch.dir.data());
        std::fill(scratch.throughput.data(), scratch.throughput.data() + 3 * n, 1.0f);
        std::fill(scratch.prev_pdf.data(), scratch.prev_pdf.data() + n, 0.0f);
        scratch.active.resize(n);
        for (size_t i = 0; i < n; ++i) scratch.active[i] = static_cast<int32_t>(i);
        return;
    }
    for (size_t i = 0; i < n; ++i) {
        const CameraSample& c = wavefront.camera_samples[i];
        const float lu = lens ? sample_uniform(wavefront.settings.sampler, c.key, c.index, 0, kDimLensU) : 0.0f;
        const float lv = lens ? sample_uniform(wavefront.settings.sampler, c.key, c.index, 0, kDimLensV) : 0.0f;
        Vec3f o, d;
        camera_ray(wavefront.scene.camera, c.film_x, c.film_y, lu, lv, o, d);
        start_path(wavefront, i, o, d);
    }
}

// Paths along given rays (the radiance cache's: n origins and directions, row by row).
inline void start_given_paths(const Wavefront& wavefront, const float* org, const float* dir, size_t n) {
    start_paths(wavefront, n);
    for (size_t i = 0; i < n; ++i) start_path(wavefront, i, load_vec3(org + 3 * i), load_vec3(dir + 3 * i));
}

inline bool scene_has_sun(const RenderScene& scene) {
    for (const Light& l : scene.lights)
        if (l.is<SunLight>()) return true;
    return false;
}

// The active paths' rays, N per packet; hit j belongs to path scratch.active[j].
inline HitBatch trace_bounce(const Wavefront& wavefront, int depth) {
    PathScratch& scratch = wavefront.scratch;
    const size_t m = scratch.active.size();
    float* ro = grow(scratch.ray_org, 3 * m);
    float* rd = grow(scratch.ray_dir, 3 * m);
    if (!scratch.rays_gathered)  // (update_paths wrote the next bounce's rays in order already)
        for (size_t j = 0; j < m; ++j) {
            const int32_t i = scratch.active[j];
            std::copy(scratch.org.data() + 3 * i, scratch.org.data() + 3 * i + 3, ro + 3 * j);
            std::copy(scratch.dir.data() + 3 * i, scratch.dir.data() + 3 * i + 3, rd + 3 * j);
        }
    HitBatch hits{grow(scratch.hit_t, m), grow(scratch.hit_prim, m), grow(scratch.hit_u, m), grow(scratch.hit_v, m)};
    scratch.timer.lap(Stage::RayGather);
    const RayBatch rays{ro, rd, 0.0f, nullptr, kInfinity};
    // camera rays are coherent: kd-tree packets; the rest one at a time through the BVH
    if (depth > 0 && wavefront.scene.bvh) trace_kernels().intersect_bvh(*wavefront.scene.bvh, rays, hits, 0, m);
    else trace_kernels().intersect(*wavefront.scene.tree, rays, hits, 0, m);
    scratch.rays_traced += m;
    (depth == 0 ? scratch.timer.times.camera_rays : scratch.timer.times.secondary_rays) += m;
    scratch.timer.lap(depth == 0 ? Stage::TraceCamera : Stage::TraceSecondary);
    return hits;
}

// The paths that go on become the next bounce's active paths, with their rays in that order
// (update_paths wrote them; none if no path goes on).
inline void next_bounce(const Wavefront& wavefront) {
    PathScratch& scratch = wavefront.scratch;
    std::swap(scratch.active, scratch.next_active);
    std::swap(scratch.ray_org, scratch.next_ray_org);
    std::swap(scratch.ray_dir, scratch.next_ray_dir);
    scratch.rays_gathered = true;
}

}  // namespace render_detail
PATINA_END_TARGET
