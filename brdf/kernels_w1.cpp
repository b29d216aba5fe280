// Kernels at width 1.
#define PATINA_KERNEL_WIDTH 1
#include "brdf/kernels_impl.h"

namespace patina {

const Kernels& kernels_w1() {
    static const Kernels k{1, &math_kernel, &search_kernel<SplitWalk::Masked>,
                           &search_kernel<SplitWalk::Sequential>, &eval_kernel, &eval_libm_kernel};
    return k;
}

}  // namespace patina
