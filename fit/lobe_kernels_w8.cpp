// Analytic-lobe kernels at width 8 (compiled with -mavx2 -mfma).
#define PATINA_KERNEL_WIDTH 8
#include "fit/lobe_kernels_impl.h"

namespace patina {

const LobeKernels& lobe_kernels_w8() {
    static const LobeKernels k{8, &eval_mixture, &sample_lobe, &sample_lambert, &sample_ward,
                             &loss_mixture};
    return k;
}

}  // namespace patina
