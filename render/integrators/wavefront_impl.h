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
inline void start_path(const Wavefront& w, size_t i, const Vec3f& o, const Vec3f& d) {
    PathScratch& sc = w.scratch;
    store_vec3(o, sc.org.data() + 3 * i);
    store_vec3(d, sc.dir.data() + 3 * i);
    std::fill(sc.throughput.data() + 3 * i, sc.throughput.data() + 3 * i + 3, 1.0f);
    sc.prev_pdf[i] = 0;  // a first segment: whatever it sees counts in full
    sc.active.push_back(static_cast<int32_t>(i));
}

// The path arrays sized for n paths, none active yet, the n results empty.
inline void start_paths(const Wavefront& w, size_t n) {
    PathScratch& sc = w.scratch;
    grow(sc.org, 3 * n);
    grow(sc.dir, 3 * n);
    grow(sc.throughput, 3 * n);
    grow(sc.prev_pdf, n);
    grow(sc.prev_pos, 3 * n);
    sc.active.clear();
    sc.rays_gathered = false;
    sc.cached.clear();  // none served by the radiance cache (start_camera_paths says otherwise)
    if (sc.cache) cache::cache_state(sc).guides.clear();  // no guides until place_guide_points
    for (size_t i = 0; i < n; ++i) {
        PathResult& r = w.results[i];
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
inline void pinhole_rays(const Camera& c, const CameraSample* cs, size_t n, float* org, float* dir) {
    const float aspect = static_cast<float>(c.width) / static_cast<float>(c.height);
    const V3 right{F(c.right[0]), F(c.right[1]), F(c.right[2])}, up{F(c.up[0]), F(c.up[1]), F(c.up[2])};
    const V3 forward{F(c.forward[0]), F(c.forward[1]), F(c.forward[2])};
    const V3 o{F(c.position[0]), F(c.position[1]), F(c.position[2])};
    for_blocks(n, [&](size_t i, int lanes) {
        alignas(64) float fx[N] = {}, fy[N] = {};
        for (int k = 0; k < lanes; ++k) {
            fx[k] = cs[i + k].fx;
            fy[k] = cs[i + k].fy;
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
inline void start_camera_paths(const Wavefront& w, size_t n) {
    start_paths(w, n);
    const bool lens = w.scene.camera.aperture_radius > 0;  // a pinhole draws no lens numbers
    if (!lens) {  // start_path for every path, the rays N at a time
        PathScratch& sc = w.scratch;
        pinhole_rays(w.scene.camera, w.camera_samples, n, sc.org.data(), sc.dir.data());
        std::fill(sc.throughput.data(), sc.throughput.data() + 3 * n, 1.0f);
        std::fill(sc.prev_pdf.data(), sc.prev_pdf.data() + n, 0.0f);
        sc.active.resize(n);
        for (size_t i = 0; i < n; ++i) sc.active[i] = static_cast<int32_t>(i);
        return;
    }
    for (size_t i = 0; i < n; ++i) {
        const CameraSample& c = w.camera_samples[i];
        const float lu = lens ? sample_uniform(w.settings.sampler, c.key, c.index, 0, kDimLensU) : 0.0f;
        const float lv = lens ? sample_uniform(w.settings.sampler, c.key, c.index, 0, kDimLensV) : 0.0f;
        Vec3f o, d;
        camera_ray(w.scene.camera, c.fx, c.fy, lu, lv, o, d);
        start_path(w, i, o, d);
    }
}

// Paths along given rays (the radiance cache's: n origins and directions, row by row).
inline void start_given_paths(const Wavefront& w, const float* org, const float* dir, size_t n) {
    start_paths(w, n);
    for (size_t i = 0; i < n; ++i) start_path(w, i, load_vec3(org + 3 * i), load_vec3(dir + 3 * i));
}


inline bool scene_has_sun(const RenderScene& s) {
    for (const Light& l : s.lights)
        if (l.is<SunLight>()) return true;
    return false;
}

// The active paths' rays, N per packet; hit j belongs to path sc.active[j].
inline HitBatch trace_bounce(const Wavefront& w, int depth) {
    PathScratch& sc = w.scratch;
    const size_t m = sc.active.size();
    float* ro = grow(sc.ray_org, 3 * m);
    float* rd = grow(sc.ray_dir, 3 * m);
    if (!sc.rays_gathered)  // (update_paths wrote the next bounce's rays in order already)
        for (size_t j = 0; j < m; ++j) {
            const int32_t i = sc.active[j];
            std::copy(sc.org.data() + 3 * i, sc.org.data() + 3 * i + 3, ro + 3 * j);
            std::copy(sc.dir.data() + 3 * i, sc.dir.data() + 3 * i + 3, rd + 3 * j);
        }
    HitBatch hits{grow(sc.hit_t, m), grow(sc.hit_prim, m), grow(sc.hit_u, m), grow(sc.hit_v, m)};
    sc.timer.lap(Stage::RayGather);
    const RayBatch rays{ro, rd, 0.0f, nullptr, kInfinity};
    // camera rays are coherent: kd-tree packets; the rest one at a time through the BVH
    if (depth > 0 && w.scene.bvh) trace_kernels().intersect_bvh(*w.scene.bvh, rays, hits, 0, m);
    else trace_kernels().intersect(*w.scene.tree, rays, hits, 0, m);
    sc.rays_traced += m;
    (depth == 0 ? sc.timer.times.camera_rays : sc.timer.times.secondary_rays) += m;
    sc.timer.lap(depth == 0 ? Stage::TraceCamera : Stage::TraceSecondary);
    return hits;
}

// The paths that go on become the next bounce's active paths, with their rays in that order
// (update_paths wrote them; none if no path goes on).
inline void next_bounce(const Wavefront& w) {
    PathScratch& sc = w.scratch;
    std::swap(sc.active, sc.next_active);
    std::swap(sc.ray_org, sc.next_ray_org);
    std::swap(sc.ray_dir, sc.next_ray_dir);
    sc.rays_gathered = true;
}

}  // namespace render_detail
PATINA_END_TARGET
