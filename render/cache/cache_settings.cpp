#include "render/cache/cache_settings.h"

namespace patina {

const SettingRange<CacheSettings> kCacheSettingRanges[11] = {
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

void check_cache_settings(const CacheSettings& s) {
    check_setting_ranges(kCacheSettingRanges, s, "cache.");
    if (s.train_max_depth < kCacheTrainMaxDepthMin || s.train_max_depth > kCacheTrainMaxDepthMax)
        fail_setting_range("cache.train_max_depth", true, kCacheTrainMaxDepthMin, kCacheTrainMaxDepthMax,
                           s.train_max_depth);
}

}  // namespace patina
