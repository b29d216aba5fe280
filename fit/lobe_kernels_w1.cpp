// Analytic-lobe kernels at width 1.
#define PATINA_KERNEL_WIDTH 1
#include "fit/lobe_kernels_impl.h"

namespace patina {

const LobeKernels& lobe_kernels_w1() {
    static const LobeKernels k{1, &eval_mixture, &sample_lobe, &sample_lambert, &sample_ward,
                             &loss_mixture};
    return k;
}

}  // namespace patina
