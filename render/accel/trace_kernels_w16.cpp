// Ray-tracing kernels for packets of 16 (compiled with PATINA_AVX512_FLAGS: AVX-512 F, VL, DQ, BW and FMA).
#define PATINA_KERNEL_WIDTH 16
#include "render/accel/trace_kernels_impl.h"

namespace patina {

const TraceKernels& trace_kernels_w16() {
    static const TraceKernels k{16, &intersect_kernel, &occluded_kernel, &intersect_bvh_kernel, &occluded_bvh_kernel,
                                  &occluded_bvh_packet_kernel};
    return k;
}

}  // namespace patina
