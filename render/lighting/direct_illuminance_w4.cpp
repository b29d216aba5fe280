// The exact direct illuminance, 4 sensors at a time (compiled with -msse4.1).
#define PATINA_KERNEL_WIDTH 4
#include "render/lighting/direct_illuminance_impl.h"

namespace patina {

const DirectIlluminanceKernels& direct_illuminance_kernels_w4() {
    static const DirectIlluminanceKernels k{4, &render_detail::direct_sum};
    return k;
}

}  // namespace patina
