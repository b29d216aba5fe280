// The exact direct illuminance, 16 sensors at a time (compiled with PATINA_AVX512_FLAGS:
// AVX-512 F, VL, DQ, BW and FMA).
#define PATINA_KERNEL_WIDTH 16
#include "render/lighting/direct_illuminance_impl.h"

namespace patina {

const DirectIlluminanceKernels& direct_illuminance_kernels_w16() {
    static const DirectIlluminanceKernels k{16, &render_detail::direct_sum};
    return k;
}

}  // namespace patina
