// The path integrator at width 4 (compiled with -msse4.1).
#define PATINA_KERNEL_WIDTH 4
#include "render/integrators/kernels_impl.h"
#include "render/lights/grid2_impl.h"

namespace patina {

const RenderKernels& render_kernels_w4() {
    static const RenderKernels k{4, &render_detail::trace_paths, &render_detail::sensor_illuminance,
                                 &render_detail::sensor_illuminance_indirect,
                                 &render_detail::grid2_w::eval_array, &render_detail::light_selection,
                                 &render_detail::cache_probe,
                                 &render_detail::build_cache_region,
                                 &render_detail::jitter_pixel_positions,
                                 &render_detail::sensor_cache_points};
    return k;
}

}  // namespace patina
