// The path tracer (integrator `path`; `direct` is the same at max_depth 1): unidirectional
// path tracing with next-event estimation and MIS, as pbrt-v4's PathIntegrator::Li, run as a
// wavefront (pbrt-v4's wavefront integrator, Laine et al. 2013): the batch's paths advance one
// bounce at a time, each stage over every path still alive, N lanes at a time.
#pragma once

#include "core/simd/kernel_width.h"
#include "render/integrators/bsdf_samples_impl.h"
#include "render/integrators/emission_impl.h"
#include "render/integrators/integrator.h"
#include "render/integrators/light_samples_impl.h"
#include "render/integrators/shading_points_impl.h"
#include "render/integrators/wavefront_impl.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// The bounces of the batch's started paths, until every one has ended.
inline void path_bounces(const Wavefront& wavefront) {
    wavefront.scratch.sampler = wavefront.settings.sampler;  // what fill_uniforms draws the points' numbers from
    for (int depth = 0; !wavefront.scratch.active.empty(); ++depth) {
        const HitBatch hits = trace_bounce(wavefront, depth);  // every path's ray, N per packet
        add_emission_and_environment(wavefront, hits, depth);  // lights hit, the environment missed: MIS-weighted
        make_shading_points(wavefront, hits, depth);           // surface hits, grouped by material
        queue_light_samples(wavefront, depth);                 // a light sample each, MIS-weighted; shadow ray queued
        sample_bsdf(wavefront, depth);                         // the next direction; throughput, Russian roulette
        resolve_shadow_rays(wavefront);                        // shadow rays in packets: the unblocked add their light
        next_bounce(wavefront);                                // the paths that go on
    }
}

// `path` for a batch of camera samples.
inline void trace_path(const Wavefront& wavefront, size_t n) {
    start_camera_paths(wavefront, n);
    wavefront.scratch.timer.lap(Stage::CameraRays);
    path_bounces(wavefront);
}

}  // namespace render_detail
PATINA_END_TARGET
