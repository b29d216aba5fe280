#include "render/cache/cache_settings.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace patina {

void check_cache_settings(const CacheSettings& s) {
    if (s.resolution < kCacheResolutionMin || s.resolution > kCacheResolutionMax)
        throw std::invalid_argument("cache.resolution: must be an integer from " + std::to_string(kCacheResolutionMin) +
                                    " to " + std::to_string(kCacheResolutionMax) + ", got " +
                                    std::to_string(s.resolution));
    if (!(s.error >= kCacheErrorMin && s.error <= kCacheErrorMax))
        throw std::invalid_argument("cache.error: must be a number in [0.01, 4], got " + std::to_string(s.error));
    if (!(s.guide >= kCacheGuideMin && s.guide <= kCacheGuideMax))
        throw std::invalid_argument("cache.guide: must be a number in [0.05, 0.95], got " + std::to_string(s.guide));
    if (s.block < kCacheBlockMin || s.block > kCacheBlockMax)
        throw std::invalid_argument("cache.block: must be an integer from " + std::to_string(kCacheBlockMin) + " to " +
                                    std::to_string(kCacheBlockMax) + ", got " + std::to_string(s.block));
    if (s.hit_paths < kCacheHitPathsMin || s.hit_paths > kCacheHitPathsMax)
        throw std::invalid_argument("cache.hit_paths: must be an integer from " + std::to_string(kCacheHitPathsMin) +
                                    " to " + std::to_string(kCacheHitPathsMax) + ", got " +
                                    std::to_string(s.hit_paths));
}

}  // namespace patina
