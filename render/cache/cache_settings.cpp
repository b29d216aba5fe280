#include "render/cache/cache_settings.h"

namespace patina {

void check_cache_settings(const CacheSettings& s) {
    check_setting_ranges(kCacheSettingRanges, s, "cache.");
    if (s.train_max_depth < kCacheTrainMaxDepthMin || s.train_max_depth > kCacheTrainMaxDepthMax)
        fail_setting_range("cache.train_max_depth", true, kCacheTrainMaxDepthMin, kCacheTrainMaxDepthMax,
                           s.train_max_depth);
}

}  // namespace patina
