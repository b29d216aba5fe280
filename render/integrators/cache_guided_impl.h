// The radiance cache's unbiased integrator (integrator `cache-guided`; thesis chapter 4, "the
// unbiased variant", docs/radiance-cache.md): the path tracer whose BSDF samples at the first
// bounces are drawn partly from a guide -- the cache's incident radiance x BSDF at nearby cache
// points, or the trained guide field (render/guiding/) -- combined with BSDF and light sampling
// by MIS. During the guide's training passes its path vertices are recorded.
#pragma once

#include "core/simd/kernel_width.h"
#include "render/cache/guided_stages_impl.h"
#include "render/guiding/guide_recording_impl.h"
#include "render/integrators/bsdf_samples_impl.h"
#include "render/integrators/cache_impl.h"
#include "render/integrators/emission_impl.h"
#include "render/integrators/integrator.h"
#include "render/integrators/light_samples_impl.h"
#include "render/integrators/shading_points_impl.h"
#include "render/integrators/wavefront_impl.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// Light sampling with MIS against the guided BSDF sampling: the density a light sample's
// direction has under the guide mixed into its BSDF density before the weights.
inline void queue_guided_light_samples(const Wavefront& wavefront, int depth) {
    if (!sample_and_evaluate_lights(wavefront, depth)) return;
    PathScratch& scratch = wavefront.scratch;
    cache::mix_light_pdfs(scratch, wavefront.settings.cache, scratch.l_local.data(), scratch.pdf.data(),
                          scratch.sorted.size());
    queue_light_shadow_rays(wavefront, depth, 1.0f);
}

// BSDF sampling where a guide serves the points: each guided point picks the guide or its
// BSDF, the guide's picks drawn from its texels, their densities the mixture's.
inline void sample_guided_bsdf(const Wavefront& wavefront, int depth) {
    if (!cache::guided_here(wavefront.scratch)) return sample_bsdf(wavefront, depth);
    draw_bsdf_numbers(wavefront, depth, true);  // every point's pick: the guide's choice reads it
    cache::guided_picks(wavefront);
    sample_materials(wavefront);
    cache::guided_directions(wavefront);
    continue_paths(wavefront, depth);
}

// The bounces of `cache-guided`'s camera paths.
inline void cache_guided_bounces(const Wavefront& wavefront) {
    PathScratch& scratch = wavefront.scratch;
    scratch.sampler = wavefront.settings.sampler;                // what fill_uniforms draws the points' numbers from
    const bool recording = guide_recording::recording(scratch);  // a training pass of the guide
    for (int depth = 0; !scratch.active.empty(); ++depth) {
        const HitBatch hits = trace_bounce(wavefront, depth);
        add_emission_and_environment(wavefront, hits, depth);
        if (recording) guide_recording::note_arrivals(wavefront);
        make_shading_points(wavefront, hits, depth);
        if (depth == 0 && cache_serves(wavefront)) {  // the guides of the first hits: nearby cache points
            CacheRayTracer tracer(wavefront.scene, wavefront.settings, wavefront.scratch);
            cache::place_guide_points(wavefront, tracer);
        }
        cache::assign_guides(wavefront, depth);
        queue_guided_light_samples(wavefront, depth);
        sample_guided_bsdf(wavefront, depth);
        if (recording) guide_recording::note_vertices(wavefront);
        resolve_shadow_rays(wavefront);
        next_bounce(wavefront);
    }
}

// `cache-guided` for a batch of camera samples.
inline void trace_cache_guided(const Wavefront& wavefront, size_t n) {
    start_camera_paths(wavefront, n);
    wavefront.scratch.timer.lap(Stage::CameraRays);
    if (guide_recording::recording(wavefront.scratch)) guide_recording::start_records(wavefront.scratch);
    cache_guided_bounces(wavefront);
    if (guide_recording::recording(wavefront.scratch)) guide_recording::finish_records(wavefront);
}

}  // namespace render_detail
PATINA_END_TARGET
