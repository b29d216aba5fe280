// Analytic-lobe kernels at width 16 (compiled with PATINA_AVX512_FLAGS: AVX-512 F, VL, DQ, BW and FMA).
#define PATINA_KERNEL_WIDTH 16
#include "fit/lobe_kernels_impl.h"

namespace patina {

const LobeKernels& lobe_kernels_w16() {
    static const LobeKernels k{16, &eval_mixture, &sample_lobe, &sample_lambert, &sample_ward,
                             &loss_mixture};
    return k;
}

}  // namespace patina
