#include "fit/lobe_kernels.h"

#include "core/width_dispatch.h"

namespace patina {

const LobeKernels& lobe_kernels_for(int width) {
    return kernels_for_width(width, lobe_kernels_w1, lobe_kernels_w4, lobe_kernels_w8, lobe_kernels_w16);
}

}  // namespace patina
