// The exact direct illuminance, 8 sensors at a time (compiled with -mavx2 -mfma).
#define PATINA_KERNEL_WIDTH 8
#include "render/lighting/direct_illuminance_impl.h"

namespace patina {

const DirectIlluminanceKernels& direct_illuminance_kernels_w8() {
    static const DirectIlluminanceKernels k{8, &render_detail::direct_sum};
    return k;
}

}  // namespace patina
