#include "render/render_options.h"

#include <stdexcept>

namespace patina {

const SettingRange<RenderOptions> kRenderOptionRanges[4] = {
    {"spp", true, 1, 1 << 20, [](const RenderOptions& o) { return double(o.spp); }},
    {"max_depth", true, 1, 1024, [](const RenderOptions& o) { return double(o.max_depth); }},
    {"aa_threshold", false, 0, 1, [](const RenderOptions& o) { return double(o.aa_threshold); }},
    {"threads", true, 0, 1024, [](const RenderOptions& o) { return double(o.threads); }},
};

void check_render_options(const RenderOptions& o) {
    check_setting_ranges(kRenderOptionRanges, o, "");
    if (o.tile_size < 0) throw std::invalid_argument("tile_size: must be at least 1 (or 0: the sampler's own)");
    if (o.max_pass_spp < 1) throw std::invalid_argument("max_pass_spp: must be at least 1");
    check_cache_settings(o.cache);
}

}  // namespace patina
