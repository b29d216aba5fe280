// Kernels at width 8 (compiled with -mavx2 -mfma).
#define PATINA_KERNEL_WIDTH 8
#include "brdf/kernels_impl.h"

namespace patina {

const Kernels& kernels_w8() {
    static const Kernels k{8, &math_kernel, &search_kernel<SplitWalk::Masked>,
                           &search_kernel<SplitWalk::Sequential>, &eval_kernel, nullptr};
    return k;
}

}  // namespace patina
