// The path integrator at width 4 (compiled with -msse4.1).
#define PATINA_KERNEL_WIDTH 4
#include "render/integrator_impl.h"

namespace patina {

const RenderKernels& render_kernels_w4() {
    static const RenderKernels k{4, &render_detail::trace_paths};
    return k;
}

}  // namespace patina
