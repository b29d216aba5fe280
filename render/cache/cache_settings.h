// The radiance cache's parameters (docs/radiance-cache.md; scene key render.cache, CLI
// --cache-*), their defaults and allowed ranges (kCacheSettingRanges, which the Python scene
// reader's checks read too, naming the key or option); check_cache_settings is the C++ side's own guard.
#pragma once

#include "render/setting_range.h"

namespace patina {

struct CacheSettings {
    int resolution = 24;  // texels per side of a hemisphere (R x R texels, equal solid angle each)
    float error = 0.5f;   // the reuse criterion's bound: B uses A when |B - A| / R_A + sqrt(1 - nA.nB) <= error
    float guide = 0.5f;   // cache-guided: the probability of drawing a bounce from the cache points...
    int guide_bounces = 1;  // ...at the first this many bounces of a path (1: the first hit's)
    int block = 8;        // pixels per side of the blocks whose close points share one reconstruction
    int hit_paths = 4;    // cache: paths from a cache point's texel hit on a glossy surface (its light split)
    // cache: the light samples a camera sample takes at its first hit, each weighing 1 / their
    // count (under an open sky the first hit's direct light is most of the image's error)
    int light_samples = 1;
    // cache-guided's trained guide (render/guiding/guide_training.h): its training passes
    // (0: none, the first bounce guided by the cache points alone) and their samples a pixel
    int train_passes = 1;
    int train_spp = 1;
    float train_guide = 0.1f;  // ...and the probability of drawing a bounce from it...
    int train_bounces = 1;     // ...at the first this many bounces of a path (1: the first hit's)
    // the training paths' max_depth (in segments, as the render's; 0: the render's). A measuring
    // knob of the low-level binding only (tools/cache_measure/variance_split.py: a render cut
    // to direct light that samples the guide trained on full paths)
    int train_max_depth = 0;
};

// Each scene-file setting's allowed range (render.cache.<key> in a scene file, --cache-<key>
// on the command line), defined here once (render/setting_range.h) and sized by its entries, so
// a setting added cannot leave a hand-kept count behind.
inline constexpr SettingRange<CacheSettings> kCacheSettingRanges[] = {
    {"resolution", true, 8, 128, [](const CacheSettings& s) { return double(s.resolution); }},
    {"error", false, 0.01, 4, [](const CacheSettings& s) { return double(s.error); }},
    {"guide", false, 0.05, 0.95, [](const CacheSettings& s) { return double(s.guide); }},
    {"guide_bounces", true, 1, 16, [](const CacheSettings& s) { return double(s.guide_bounces); }},
    {"block", true, 1, 16, [](const CacheSettings& s) { return double(s.block); }},
    {"hit_paths", true, 1, 16, [](const CacheSettings& s) { return double(s.hit_paths); }},
    {"light_samples", true, 1, 16, [](const CacheSettings& s) { return double(s.light_samples); }},
    {"train_passes", true, 0, 8, [](const CacheSettings& s) { return double(s.train_passes); }},
    {"train_spp", true, 1, 16, [](const CacheSettings& s) { return double(s.train_spp); }},
    {"train_guide", false, 0.05, 0.95, [](const CacheSettings& s) { return double(s.train_guide); }},
    {"train_bounces", true, 1, 16, [](const CacheSettings& s) { return double(s.train_bounces); }},
};

// train_max_depth, a knob of the low-level binding only (no scene key): its range
constexpr int kCacheTrainMaxDepthMin = 0, kCacheTrainMaxDepthMax = 1024;

// Throws std::invalid_argument naming the key (cache.resolution, ...) and its range.
void check_cache_settings(const CacheSettings& s);

}  // namespace patina
