// What a render job is asked to do (RenderJob's one argument; patina._core.RenderOptions in
// Python, built by python/patina/render/run.py's job_settings from the scene file). max_depth
// and the seed are the scene file's own (docs/scene.md): the job turns them into the kernels'
// path vertices (path_vertices) and the samplers' 32-bit stream key (stream_seed).
#pragma once

#include <cstdint>

#include "render/antialiasing/adaptive_sampler.h"
#include "render/cache/cache_settings.h"
#include "render/integrators/integrator.h"
#include "render/samplers/sample_numbers.h"
#include "render/setting_range.h"

namespace patina {

struct RenderOptions {
    int spp = 16;       // samples a pixel (the adaptive sampler: patterns a pixel)
    int max_depth = 8;  // longest path in segments, Mitsuba 3's convention: 2 = direct light, 3 = one bounce
    uint64_t seed = 0;  // the scene file's seed, 0 to 2^63 - 1
    int threads = 0;    // worker threads; 0: all hardware threads
    int width = 0;      // SIMD width 1, 4, 8, 16; 0: the widest the CPU runs
    // 0: the sampler's own, 16 for the uniform sampler, kAdaptiveTileSize for the adaptive
    // one (its levels 2 and 3 trace scattered pixels: larger tiles make larger wavefronts)
    int tile_size = 0;
    int passes = 8;         // a pixel's samples are split into at least this many passes (fewer if spp is smaller)...
    int max_pass_spp = 16;  // ...of at most this many samples, so a cancel never waits long for a pass
    // The pixel sampler: uniform (spp jittered samples a pixel) or the adaptive antialiasing
    // (render/antialiasing/adaptive_sampler.h; spp patterns a pixel, one a pass, each of 1 to 25 rays).
    enum class Aa { Uniform, Adaptive } aa = Aa::Uniform;
    float aa_threshold = kDefaultAaThreshold;  // the adaptive sampler's contrast threshold, in [0, 1]
    bool indirect_illuminance = false;  // the illuminance AOV counts reflected light (IntegratorSettings)
    // The paths' numbers (render/samplers/sample_numbers.h): Owen-scrambled Sobol or independent.
    SamplerKind sampler = SamplerKind::Sobol;
    bool stage_cpu_time = false;  // stage timers on each thread's CPU time, not wall time (render/integrators/stage_timer.h)
    IntegratorMode mode = IntegratorMode::Path;  // path, or the radiance cache's (docs/radiance-cache.md)
    CacheSettings cache;
};

// The options with a range, defined here once (render/setting_range.h) and sized by its
// entries: the scene reader's render.spp, render.max_depth, render.aa_threshold and the
// command line's --threads read it.
inline constexpr SettingRange<RenderOptions> kRenderOptionRanges[] = {
    {"spp", true, 1, 1 << 20, [](const RenderOptions& o) { return double(o.spp); }},
    {"max_depth", true, 1, 1024, [](const RenderOptions& o) { return double(o.max_depth); }},
    {"aa_threshold", false, 0, 1, [](const RenderOptions& o) { return double(o.aa_threshold); }},
    {"threads", true, 0, 1024, [](const RenderOptions& o) { return double(o.threads); }},
};

// Throws std::invalid_argument naming the option (spp, cache.error, ...) and its range.
void check_render_options(const RenderOptions& options);

// The documented seeds are 0 to 2^63 - 1; the samplers key their streams by 32 bits. Seeds
// below 2^32 are used as they are (images stay the same), higher bits are mixed into them.
inline uint32_t stream_seed(uint64_t seed) {
    return static_cast<uint32_t>(seed) ^ (static_cast<uint32_t>(seed >> 32) * 0x9e3779b1u);
}

}  // namespace patina
