// Run-time choice of the exact direct illuminance's width, and its split over threads.
#include "render/lighting/direct_illuminance.h"

#include "core/parallel.h"
#include "core/width_dispatch.h"

namespace patina {

const DirectIlluminanceKernels& direct_illuminance_kernels_for(int width) {
    return kernels_for_width<DirectIlluminanceKernels>(width, direct_illuminance_kernels_w1,
                                                       direct_illuminance_kernels_w4, direct_illuminance_kernels_w8,
                                                       direct_illuminance_kernels_w16);
}

void direct_illuminance(const DirectLighting& lighting, const IlluminanceSensors& sensors, float* lux,
                        float* per_source, int width, int threads) {
    const DirectIlluminanceKernels& k = direct_illuminance_kernels_for(width);
    // chunks of whole packets at every width; each sensor's sum does not depend on its chunk
    constexpr size_t kGrain = 256;
    parallel_for(sensors.count, kGrain, threads,
                 [&](size_t begin, size_t end) { k.sum(lighting, sensors, lux, per_source, begin, end); });
}

}  // namespace patina
