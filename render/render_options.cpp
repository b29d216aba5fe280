#include "render/render_options.h"

#include <stdexcept>

namespace patina {

void check_render_options(const RenderOptions& o) {
    check_setting_ranges(kRenderOptionRanges, o, "");
    if (o.tile_size < 0) throw std::invalid_argument("tile_size: must be at least 1 (or 0: the sampler's own)");
    if (o.max_pass_spp < 1) throw std::invalid_argument("max_pass_spp: must be at least 1");
    check_cache_settings(o.cache);
}

}  // namespace patina
