// The RGL evaluator at width 16 (compiled with AVX-512).
#define PATINA_KERNEL_WIDTH 16
#include "brdf/rgl/rgl_kernels_impl.h"

namespace patina {

const RglKernels& rgl_kernels_w16() {
    static const RglKernels k{16, &rgl_eval_kernel, &rgl_pdf_kernel, &rgl_sample_kernel};
    return k;
}

}  // namespace patina
