// The RGL evaluator at width 1.
#define PATINA_KERNEL_WIDTH 1
#include "brdf/rgl/rgl_kernels_impl.h"

namespace patina {

const RglKernels& rgl_kernels_w1() {
    static const RglKernels k{1, &rgl_eval_kernel, &rgl_pdf_kernel, &rgl_sample_kernel};
    return k;
}

}  // namespace patina
