// Analytic-lobe kernels at width 4 (compiled with -msse4.1).
#define PATINA_KERNEL_WIDTH 4
#include "fit/lobe_kernels_impl.h"

namespace patina {

const LobeKernels& lobe_kernels_w4() {
    static const LobeKernels k{4, &eval_mixture, &sample_lobe, &sample_lambert, &sample_ward,
                             &loss_mixture};
    return k;
}

}  // namespace patina
