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
    if (s.train_passes < kCacheTrainPassesMin || s.train_passes > kCacheTrainPassesMax)
        throw std::invalid_argument("cache.train_passes: must be an integer from " +
                                    std::to_string(kCacheTrainPassesMin) + " to " +
                                    std::to_string(kCacheTrainPassesMax) + ", got " + std::to_string(s.train_passes));
    if (s.train_spp < kCacheTrainSppMin || s.train_spp > kCacheTrainSppMax)
        throw std::invalid_argument("cache.train_spp: must be an integer from " + std::to_string(kCacheTrainSppMin) +
                                    " to " + std::to_string(kCacheTrainSppMax) + ", got " + std::to_string(s.train_spp));
    if (!(s.train_guide >= kCacheTrainGuideMin && s.train_guide <= kCacheTrainGuideMax))
        throw std::invalid_argument("cache.train_guide: must be a number in [0.05, 0.95], got " +
                                    std::to_string(s.train_guide));
    if (s.train_bounces < kCacheTrainBouncesMin || s.train_bounces > kCacheTrainBouncesMax)
        throw std::invalid_argument("cache.train_bounces: must be an integer from " +
                                    std::to_string(kCacheTrainBouncesMin) + " to " +
                                    std::to_string(kCacheTrainBouncesMax) + ", got " + std::to_string(s.train_bounces));
    if (s.train_max_depth < kCacheTrainMaxDepthMin || s.train_max_depth > kCacheTrainMaxDepthMax)
        throw std::invalid_argument("cache_train_max_depth: must be an integer from " +
                                    std::to_string(kCacheTrainMaxDepthMin) + " to " +
                                    std::to_string(kCacheTrainMaxDepthMax) + ", got " +
                                    std::to_string(s.train_max_depth));
}

}  // namespace patina
