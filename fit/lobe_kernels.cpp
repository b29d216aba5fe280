#include "fit/lobe_kernels.h"

#include "core/cpu.h"

namespace patina {

const LobeKernels& lobe_kernels_for(int width) {
    switch (resolve_width(width)) {
        case 8: return lobe_kernels_w8();
        case 4: return lobe_kernels_w4();
        default: return lobe_kernels_w1();
    }
}

}  // namespace patina
