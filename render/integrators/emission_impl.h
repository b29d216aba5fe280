// The emission a bounce's rays see (an integrator's stage): an area light hit, MIS-weighted
// against light sampling after a BSDF sample; a miss sees the environment and the sun.
#pragma once

#include <algorithm>

#include "core/simd/kernel_width.h"
#include "render/integrators/integrator.h"
#include "render/integrators/wavefront_impl.h"
#include "render/lights/environment_impl.h"
#include "render/lights/sampling_impl.h"
#include "render/lights/selection_impl.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// Misses see the environment, N directions at a time: its radiance and (for MIS after a
// BRDF sample: depth > 0) the density of light sampling; and the sun's disc, where they go
// through it.
inline void add_environment(const Wavefront& wavefront, int depth) {
    const RenderScene& scene = wavefront.scene;
    PathScratch& scratch = wavefront.scratch;
    const size_t n = scratch.misses.size();
    if (n == 0) return;
    const float* thr = scratch.throughput.data();
    const float* prev_pdf = scratch.prev_pdf.data();
    float* d = grow(scratch.miss_dir, 3 * n);
    float* le = grow(scratch.miss_rgb, 3 * n);
    float* lp = grow(scratch.miss_pdf, n);
    for (size_t j = 0; j < n; ++j)
        std::copy(scratch.dir.data() + 3 * scratch.misses[j], scratch.dir.data() + 3 * scratch.misses[j] + 3,
                  d + 3 * j);
    // a path's first segment (prev_pdf 0: start_path) is not weighed against light sampling
    const bool with_pdf = depth > 0 && wavefront.can_sample_lights;
    if (scene.env.present)
        for_blocks(n, [&](size_t i, int lanes) {
            F r, g, b;
            const F p = env_w::radiance_and_pdf(scene.env, load_rows(d, i, lanes), with_pdf, r, g, b);
            store_rows(le, i, lanes, r, g, b);
            store_lanes(lp, i, lanes, p);
        });
    const int env_light = static_cast<int>(scene.lights.size());
    // without local lights (or with the environment alone) the selection does not depend on
    // the point: the environment's probability computed once (the same operations as per point)
    const bool local = selection_is_local(scene);
    const float env_selection =
        scene.env.present && !local ? selection_probability(scene, Vec3f{0, 0, 0}, env_light) : 0.0f;
    for (size_t j = 0; j < n; ++j) {
        const int32_t i = scratch.misses[j];
        const Vec3f from = load_vec3(scratch.prev_pos.data() + 3 * i);
        const bool mis = prev_pdf[i] > 0 && wavefront.can_sample_lights;  // after a BRDF sample (not a camera ray)
        if (scene.env.present) {
            const float wt =
                mis ? power_heuristic(prev_pdf[i],
                                      (local ? selection_probability(scene, from, env_light) : env_selection) * lp[j])
                    : 1.0f;
            for (int k = 0; k < 3; ++k) wavefront.results[i].rgb[k] += thr[3 * i + k] * le[3 * j + k] * wt;
        }
        for (size_t li = 0; li < scene.lights.size(); ++li) {
            if (!scene.lights[li].is<SunLight>()) continue;
            const SunLight& sun = scene.lights[li].as<SunLight>();
            if (!(dot(load_vec3(d + 3 * j), load_vec3(sun.direction)) >= sun.cos_sun)) continue;
            const float wt = mis ? power_heuristic(prev_pdf[i], selection_probability(scene, from, int(li)) /
                                                                    (2.0f * kPi * sun.one_minus_cos))
                                 : 1.0f;
            for (int k = 0; k < 3; ++k) wavefront.results[i].rgb[k] += thr[3 * i + k] * sun.radiance[k] * wt;
        }
    }
}

// Emission seen: an area light hit (MIS-weighted after a BRDF sample) adds its radiance; a
// miss sees the environment and the sun.
inline void add_emission_and_environment(const Wavefront& wavefront, const HitBatch& hits, int depth) {
    const RenderScene& scene = wavefront.scene;
    PathScratch& scratch = wavefront.scratch;
    scratch.misses.clear();
    const bool emission = depth > 0 || wavefront.first_emission;
    for (size_t j = 0; j < scratch.active.size(); ++j) {
        const int32_t i = scratch.active[j];
        const int32_t prim = hits.prim[j];
        if (prim < 0) {
            if (emission && (scene.env.present || wavefront.has_sun)) scratch.misses.push_back(i);
            continue;
        }
        const Material& mat = scene.materials[scene.tri_material[prim]];
        if (!mat.is<Emitter>()) continue;
        const int light = mat.as<Emitter>().light;
        const AreaLight& l = area_of(scene.lights[light]);
        const Vec3f ng = load_vec3(scene.tree->normals.data() + 3 * static_cast<size_t>(prim));  // quads: their normal
        const float facing = -dot(load_vec3(scratch.dir.data() + 3 * i), ng);
        if (emission && (facing > 0 || (l.two_sided && facing < 0))) {
            float wt = 1.0f;
            if (scratch.prev_pdf[i] > 0 && wavefront.can_sample_lights)
                wt = power_heuristic(
                    scratch.prev_pdf[i],
                    area_light_pdf(scene, load_vec3(scratch.prev_pos.data() + 3 * i), light, facing, hits.t[j]));
            const float* throughput = scratch.throughput.data() + 3 * i;
            for (int k = 0; k < 3; ++k) wavefront.results[i].rgb[k] += throughput[k] * l.radiance[k] * wt;
        }
        if (depth == 0) wavefront.results[i].depth = hits.t[j];
    }
    add_environment(wavefront, depth);
    scratch.timer.lap(Stage::Emission);
}

}  // namespace render_detail
PATINA_END_TARGET
