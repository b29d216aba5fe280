// The exact direct illuminance, one sensor at a time: the scalar path, the same code at
// width 1 (baseline flags).
#define PATINA_KERNEL_WIDTH 1
#include "render/lighting/direct_illuminance_impl.h"

namespace patina {

const DirectIlluminanceKernels& direct_illuminance_kernels_w1() {
    static const DirectIlluminanceKernels k{1, &render_detail::direct_sum};
    return k;
}

}  // namespace patina
