// Ray-tracing kernels for packets of 1 (single rays).
#define PATINA_KERNEL_WIDTH 1
#include "render/accel/trace_kernels_impl.h"

namespace patina {

const TraceKernels& trace_kernels_w1() {
    static const TraceKernels k{1, &intersect_kernel, &occluded_kernel, &intersect_bvh_kernel, &occluded_bvh_kernel,
                                  &occluded_bvh_packet_kernel};
    return k;
}

}  // namespace patina
