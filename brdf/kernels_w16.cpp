// Kernels at width 16 (compiled with PATINA_AVX512_FLAGS: AVX-512 F, VL, DQ, BW and FMA).
#define PATINA_KERNEL_WIDTH 16
#include "brdf/kernels_impl.h"

namespace patina {

const Kernels& kernels_w16() {
    static const Kernels k{16, &math_kernel, &search_kernel<SplitWalk::Masked>,
                           &search_kernel<SplitWalk::Sequential>, &eval_kernel, nullptr};
    return k;
}

}  // namespace patina
