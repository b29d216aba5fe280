// The RGL evaluator at width 4 (compiled with -msse4.1).
#define PATINA_KERNEL_WIDTH 4
#include "brdf/rgl/rgl_kernels_impl.h"

namespace patina {

const RglKernels& rgl_kernels_w4() {
    static const RglKernels k{4, &rgl_eval_kernel, &rgl_pdf_kernel, &rgl_sample_kernel};
    return k;
}

}  // namespace patina
