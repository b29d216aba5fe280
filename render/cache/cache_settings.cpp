#include "render/cache/cache_settings.h"

#include <sstream>
#include <stdexcept>
#include <string>

namespace patina {

const CacheSettingRange kCacheSettingRanges[9] = {
    {"resolution", true, 8, 128, [](const CacheSettings& s) { return double(s.resolution); }},
    {"error", false, 0.01, 4, [](const CacheSettings& s) { return double(s.error); }},
    {"guide", false, 0.05, 0.95, [](const CacheSettings& s) { return double(s.guide); }},
    {"block", true, 1, 16, [](const CacheSettings& s) { return double(s.block); }},
    {"hit_paths", true, 1, 16, [](const CacheSettings& s) { return double(s.hit_paths); }},
    {"train_passes", true, 0, 8, [](const CacheSettings& s) { return double(s.train_passes); }},
    {"train_spp", true, 1, 16, [](const CacheSettings& s) { return double(s.train_spp); }},
    {"train_guide", false, 0.05, 0.95, [](const CacheSettings& s) { return double(s.train_guide); }},
    {"train_bounces", true, 1, 16, [](const CacheSettings& s) { return double(s.train_bounces); }},
};

namespace {

std::string shown(double v) {
    std::ostringstream o;
    o << v;
    return o.str();
}

bool in_range(const CacheSettingRange& r, double v) {
    if (r.integer) return v >= r.lo && v <= r.hi;
    // a float setting against its bounds as floats, as the scene file's 0.01 arrives (0.01f)
    const float f = static_cast<float>(v);
    return f >= static_cast<float>(r.lo) && f <= static_cast<float>(r.hi);
}

}  // namespace

void check_cache_settings(const CacheSettings& s) {
    for (const CacheSettingRange& r : kCacheSettingRanges) {
        const double v = r.value(s);
        if (in_range(r, v)) continue;
        const std::string range = r.integer ? "an integer from " + shown(r.lo) + " to " + shown(r.hi)
                                            : "a number in [" + shown(r.lo) + ", " + shown(r.hi) + "]";
        throw std::invalid_argument(std::string("cache.") + r.key + ": must be " + range + ", got " + shown(v));
    }
    if (s.train_max_depth < kCacheTrainMaxDepthMin || s.train_max_depth > kCacheTrainMaxDepthMax)
        throw std::invalid_argument("cache_train_max_depth: must be an integer from " +
                                    std::to_string(kCacheTrainMaxDepthMin) + " to " +
                                    std::to_string(kCacheTrainMaxDepthMax) + ", got " +
                                    std::to_string(s.train_max_depth));
}

}  // namespace patina
