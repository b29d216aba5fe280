#include "render/integrators/integrator.h"

#include "core/width_dispatch.h"

namespace patina {

const RenderKernels& render_kernels_for(int width) {
    return kernels_for_width(width, render_kernels_w1, render_kernels_w4, render_kernels_w8, render_kernels_w16);
}

}  // namespace patina
