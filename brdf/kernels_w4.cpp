// Kernels at width 4 (compiled with -msse4.1).
#define PATINA_KERNEL_WIDTH 4
#include "brdf/kernels_impl.h"

namespace patina {

const Kernels& kernels_w4() {
    static const Kernels k{4, &math_kernel, &search_kernel<SplitWalk::Masked>,
                           &search_kernel<SplitWalk::Sequential>, &eval_kernel, nullptr};
    return k;
}

}  // namespace patina
