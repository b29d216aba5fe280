// The RGL evaluator at width 8 (compiled with -mavx2 -mfma).
#define PATINA_KERNEL_WIDTH 8
#include "brdf/rgl/rgl_kernels_impl.h"

namespace patina {

const RglKernels& rgl_kernels_w8() {
    static const RglKernels k{8, &rgl_eval_kernel, &rgl_pdf_kernel, &rgl_sample_kernel};
    return k;
}

}  // namespace patina
