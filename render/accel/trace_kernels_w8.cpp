// Ray-tracing kernels for packets of 8 (compiled with -mavx2 -mfma).
#define PATINA_KERNEL_WIDTH 8
#include "render/accel/trace_kernels_impl.h"

namespace patina {

const TraceKernels& trace_kernels_w8() {
    static const TraceKernels k{8, &intersect_kernel, &occluded_kernel, &intersect_bvh_kernel, &occluded_bvh_kernel,
                                  &occluded_bvh_packet_kernel};
    return k;
}

}  // namespace patina
