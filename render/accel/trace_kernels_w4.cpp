// Ray-tracing kernels for packets of 4 (compiled with -msse4.1).
#define PATINA_KERNEL_WIDTH 4
#include "render/accel/trace_kernels_impl.h"

namespace patina {

const TraceKernels& trace_kernels_w4() {
    static const TraceKernels k{4, &intersect_kernel, &occluded_kernel, &intersect_bvh_kernel, &occluded_bvh_kernel,
                                  &occluded_bvh_packet_kernel};
    return k;
}

}  // namespace patina
