// The Morton order of sensor points (sensor_order.h).
#include "render/lighting/sensor_order.h"

#include <algorithm>
#include <cmath>

namespace patina {
namespace {

constexpr int kBits = 10;

// The 10 low bits of v, two places apart, for interleaving three coordinates.
uint32_t spread_bits(uint32_t v) {
    v = (v | (v << 16)) & 0x030000FFu;
    v = (v | (v << 8)) & 0x0300F00Fu;
    v = (v | (v << 4)) & 0x030C30C3u;
    return (v | (v << 2)) & 0x09249249u;
}

}  // namespace

std::vector<uint32_t> morton_order(const float* points, size_t n) {
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < n; ++i) {
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], points[3 * i + a]);
            hi[a] = std::max(hi[a], points[3 * i + a]);
        }
    }
    float cells_per_unit[3];
    for (int a = 0; a < 3; ++a) cells_per_unit[a] = hi[a] > lo[a] ? ((1 << kBits) - 1) / (hi[a] - lo[a]) : 0.0f;
    std::vector<uint64_t> keyed(n);  // code << 32 | index: one sort, ties in input order
    for (size_t i = 0; i < n; ++i) {
        uint32_t code = 0;
        for (int a = 0; a < 3; ++a) {
            const float cell = std::min((points[3 * i + a] - lo[a]) * cells_per_unit[a], float((1 << kBits) - 1));
            code |= spread_bits(static_cast<uint32_t>(cell)) << a;
        }
        keyed[i] = (uint64_t(code) << 32) | i;
    }
    std::sort(keyed.begin(), keyed.end());
    std::vector<uint32_t> order(n);
    for (size_t i = 0; i < n; ++i) order[i] = static_cast<uint32_t>(keyed[i]);
    return order;
}

}  // namespace patina
