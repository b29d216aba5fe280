// Run-time choice of the exact direct illuminance's width, the sensors' order and the split
// over threads.
#include "render/lighting/direct_illuminance.h"

#include <cstdint>
#include <vector>

#include "core/parallel.h"
#include "core/width_dispatch.h"
#include "render/lighting/sensor_order.h"

namespace patina {

const DirectIlluminanceKernels& direct_illuminance_kernels_for(int width) {
    return kernels_for_width<DirectIlluminanceKernels>(width, direct_illuminance_kernels_w1,
                                                       direct_illuminance_kernels_w4, direct_illuminance_kernels_w8,
                                                       direct_illuminance_kernels_w16);
}

namespace {

// The sensors' rows (n x 3) in `order`.
std::vector<float> rows_in_order(const float* rows, const std::vector<uint32_t>& order) {
    std::vector<float> out(3 * order.size());
    for (size_t i = 0; i < order.size(); ++i)
        for (int a = 0; a < 3; ++a) out[3 * i + a] = rows[3 * size_t(order[i]) + a];
    return out;
}

}  // namespace

void direct_illuminance(const DirectLighting& lighting, const IlluminanceSensors& sensors, float* lux,
                        float* per_source, int width, int threads) {
    const DirectIlluminanceKernels& k = direct_illuminance_kernels_for(width);
    // the sum runs over the sensors in Morton order (sensor_order.h), its results put back
    const size_t n = sensors.count;
    const std::vector<uint32_t> order = morton_order(sensors.points, n);
    const std::vector<float> points = rows_in_order(sensors.points, order);
    const std::vector<float> normals = sensors.normals ? rows_in_order(sensors.normals, order) : std::vector<float>();
    const IlluminanceSensors sorted{sensors.kind, points.data(), sensors.normals ? normals.data() : nullptr, n};
    std::vector<float> sums(n), terms(per_source ? lighting.count * n : 0);
    float* sorted_terms = per_source ? terms.data() : nullptr;
    // chunks of whole packets at every width; each sensor's sum does not depend on its chunk
    constexpr size_t kGrain = 256;
    parallel_for(n, kGrain, threads,
                 [&](size_t begin, size_t end) { k.sum(lighting, sorted, sums.data(), sorted_terms, begin, end); });
    for (size_t i = 0; i < n; ++i) lux[order[i]] = sums[i];
    for (size_t s = 0; per_source && s < lighting.count; ++s)
        for (size_t i = 0; i < n; ++i) per_source[s * n + order[i]] = terms[s * n + i];
}

}  // namespace patina
