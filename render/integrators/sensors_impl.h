// Illuminance sensors (patina illuminance, and the illuminance AOV's indirect part): direct
// illuminance by the renderer's light sampling and shadow packets with the sensor's cosine for
// a BRDF; indirect illuminance by sensor paths, cosine-weighted, traced by the path tracer.
#pragma once

#include <algorithm>
#include <vector>

#include "core/constants.h"
#include "core/simd/kernel_width.h"
#include "render/integrators/integrator.h"
#include "render/integrators/path_impl.h"
#include "render/integrators/shadow_rays_impl.h"
#include "render/integrators/wavefront_impl.h"
#include "render/lights/sampling_impl.h"
#include "render/samplers/rng.h"
#include "render/samplers/sample_numbers.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// Sensor paths: path i starts at sensor scratch.sensors[i] (its point, geometric normal and
// frame) along a cosine-weighted direction about its normal, drawn from the lens dimensions
// of wavefront.camera_samples[i].key (a sensor has no lens). A direction below the geometric surface (a bent
// shading normal) starts no path: it adds nothing, as the estimator of a sensor on that
// surface should. Throughput 1: the radiance found, times pi, is the illuminance estimate
// (E = integral of L cos over the hemisphere = pi x the mean of L under cosine sampling).
inline void start_sensor_paths(const Wavefront& wavefront, size_t n) {
    start_paths(wavefront, n);
    for (size_t i = 0; i < n; ++i) {
        const ShadingPoint& sp = wavefront.scratch.sensors[i];
        const CameraSample& c = wavefront.camera_samples[i];
        const float u1 = sample_uniform(wavefront.settings.sampler, c.key, c.index, 0, kDimLensU);
        const float u2 = sample_uniform(wavefront.settings.sampler, c.key, c.index, 0, kDimLensV);
        const float radius = std::sqrt(u1), phi = kTwoPi * u2;
        const Vec3f l{radius * std::cos(phi), radius * std::sin(phi), std::sqrt(std::max(1.0f - u1, 0.0f))};
        const Vec3f d = normalize(to_world(sp, l));
        if (dot(d, sp.ng) > 0) start_path(wavefront, i, sp.p + wavefront.ray_offset * sp.ng, d);
    }
}

// The lux a sensor path's radiance stands for: pi x 683 lm/W x its luminance.
inline float sensor_path_lux(const PathResult& r) { return kPi * kLumensPerWatt * luminance(r.rgb); }

// Traces scratch.sensor_samples.size() sensor paths from scratch.sensors (start_sensor_paths) with at
// most settings.max_depth vertices each, into scratch.sensor_results.
inline void trace_sensor_paths(const RenderScene& scene, const IntegratorSettings& settings, PathScratch& scratch) {
    const size_t n = scratch.sensor_samples.size();
    scratch.sensor_results.resize(n);
    IntegratorSettings inner = settings;
    inner.indirect_illuminance = false;  // the sensors are not sensors again
    Wavefront wavefront{scene,
                inner,
                scratch.sensor_samples.data(),
                scratch.sensor_results.data(),
                scratch,
                lights_emit(scene),
                scene_has_sun(scene),
                scene.ray_offset};
    wavefront.first_emission = false;
    start_sensor_paths(wavefront, n);
    scratch.timer.lap(Stage::CameraRays);  // a path's start counts as camera rays, a sensor's too
    path_bounces(wavefront);
}

// A sensor path's stream key: the key of the sample's stream, salted, so it draws numbers
// of its own (the same index: with Sobol, a pixel's sensor paths are one sequence too) and
// leaves the camera path's (and the direct light sampling's) unchanged.
inline uint32_t sensor_path_key(uint32_t key) { return hash_u32(key ^ 0x5f3759dfu); }

// The illuminance AOV's indirect part (IntegratorSettings::indirect_illuminance): each first
// hit of the batch's camera paths a sensor (scratch.sensors, kept by fill_shading_points), its
// sensor path one vertex shorter than the camera path, its lux added to the path's result.
inline void add_indirect_illuminance(const RenderScene& scene, const IntegratorSettings& settings,
                                     const CameraSample* camera_samples, PathResult* out, PathScratch& scratch) {
    if (!settings.indirect_illuminance || settings.max_depth < 2 || scratch.sensors.empty()) return;
    scratch.sensor_samples.resize(scratch.sensors.size());
    for (size_t q = 0; q < scratch.sensors.size(); ++q) {
        const CameraSample& c = camera_samples[scratch.sensors[q].path];
        scratch.sensor_samples[q] = CameraSample{0, 0, sensor_path_key(c.key), c.index};
    }
    IntegratorSettings inner = settings;
    inner.max_depth = settings.max_depth - 1;
    inner.mode = IntegratorMode::Path;  // the sensors' paths are plain paths
    trace_sensor_paths(scene, inner, scratch);
    for (size_t q = 0; q < scratch.sensors.size(); ++q)
        out[scratch.sensors[q].path].illuminance += sensor_path_lux(scratch.sensor_results[q]);
}

// Sensor i (point and normal from the arrays) as shading point q: its frame about the normal.
inline ShadingPoint sensor_point(const float* points, const float* normals, size_t i, size_t q) {
    ShadingPoint sp;
    sp.p = load_vec3(points + 3 * i);
    sp.ng = normalize(load_vec3(normals + 3 * i));
    sp.n = sp.ng;
    orthonormal_frame(sp.n, sp.t, sp.b);
    sp.path = static_cast<int32_t>(q);
    sp.material = 0;
    sp.eta = 1;
    return sp;
}

// Direct illuminance on sensors (patina illuminance): the same light sampling and shadow
// packets as the renderer's, with the sensor's cosine instead of a BRDF.
void sensor_illuminance(const RenderScene& scene, const float* points, const float* normals, size_t begin, size_t end,
                        int samples, uint32_t seed, float* lux, PathScratch& scratch) {
    enter_kernel();
    scratch.timer.start();  // its laps (in sample_lights) count as light sampling
    const size_t np = end - begin;
    std::fill(lux + begin, lux + end, 0.0f);
    if (np == 0 || !lights_emit(scene)) return;
    scratch.sorted.resize(np);
    for (size_t q = 0; q < np; ++q) scratch.sorted[q] = sensor_point(points, normals, begin + q, q);
    const float eps = scene.ray_offset;
    std::vector<double> sum(np, 0.0);
    scratch.point_keys.resize(np);
    scratch.point_index.resize(np);
    scratch.sampler = SamplerKind::Independent;
    for (int k = 0; k < samples; ++k) {
        for (size_t q = 0; q < np; ++q) {
            const uint32_t key = stream_key(seed, static_cast<uint32_t>(begin + q));
            scratch.point_keys[q] = static_cast<int32_t>(key);
            scratch.point_index[q] = k;
        }
        sample_lights(scene, scratch, 0, np);
        clear_shadow_rays(scratch);
        for (size_t q = 0; q < np; ++q) {
            if (!scratch.light_samples.usable[q]) continue;
            const ShadingPoint& sp = scratch.sorted[q];
            const LightSample ls = load_light_sample(scratch, q);
            const float cos_s = dot(ls.dir, sp.n);
            if (!(cos_s > 0)) continue;
            const float none[3] = {0, 0, 0};
            queue_shadow_ray(scratch, static_cast<int32_t>(q), sp.p, sp.n, eps, ls, none,
                             kLumensPerWatt * luminance(ls.rgb) * cos_s / ls.pdf);
        }
        const uint8_t* blocked = trace_shadow_rays(scene, scratch);
        for (size_t j = 0; j < scratch.shadow_rays.path.size(); ++j)
            if (!blocked[j]) sum[scratch.shadow_rays.path[j]] += scratch.shadow_rays.lux[j];
    }
    for (size_t q = 0; q < np; ++q) lux[begin + q] = static_cast<float>(sum[q] / samples);
}

// Indirect illuminance on sensors (patina illuminance --indirect): per sample, every sensor's
// path traced as one wavefront (trace_sensor_paths), its lux added to the sensor's sum.
void sensor_illuminance_indirect(const RenderScene& scene, const IntegratorSettings& settings, const float* points,
                                 const float* normals, size_t begin, size_t end, int samples, uint32_t seed, float* lux,
                                 PathScratch& scratch) {
    enter_kernel();
    const size_t np = end - begin;
    if (np == 0 || !lights_emit(scene) || settings.max_depth < 1) return;
    std::vector<double> sum(np, 0.0);
    scratch.sensors.resize(np);  // the sensor paths leave them as they are (no sensors of their own)
    for (size_t q = 0; q < np; ++q) scratch.sensors[q] = sensor_point(points, normals, begin + q, q);
    scratch.sensor_samples.resize(np);
    for (int k = 0; k < samples; ++k) {
        for (size_t q = 0; q < np; ++q) {
            const uint32_t key = stream_key(seed, static_cast<uint32_t>(begin + q));
            scratch.sensor_samples[q] = CameraSample{0, 0, sensor_path_key(key), static_cast<uint32_t>(k)};
        }
        trace_sensor_paths(scene, settings, scratch);
        for (size_t q = 0; q < np; ++q) sum[q] += sensor_path_lux(scratch.sensor_results[q]);
    }
    for (size_t q = 0; q < np; ++q) lux[begin + q] += static_cast<float>(sum[q] / samples);
}

}  // namespace render_detail
PATINA_END_TARGET
