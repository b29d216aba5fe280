// The random numbers of many paths for one use at one bounce (render/samplers/sample_numbers.h),
// N points at a time: what light selection, light sampling and BRDF sampling draw per point.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "core/simd/kernel_width.h"
#include "render/integrators/integrator.h"
#include "render/samplers/sample_numbers.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// out[q] = sample_uniform(sc.sampler, sc.point_keys[q], sc.point_index[q], depth, d), for
// the points q in [first, first + n) (out indexed by q as well).
inline void fill_uniforms(const PathScratch& sc, size_t first, size_t n, int depth, RandomDim d, float* out) {
    const int32_t* keys = sc.point_keys.data() + first;
    const int32_t* index = sc.point_index.data() + first;
    out += first;
    for_blocks(n, [&](size_t i, int lanes) {
        int32_t key_pad[N] = {}, index_pad[N] = {};
        std::copy(keys + i, keys + i + lanes, key_pad);
        std::copy(index + i, index + i + lanes, index_pad);
        uint32_t all = 0;
        for (int k = 0; k < lanes; ++k) all |= static_cast<uint32_t>(index_pad[k]);
        store_lanes(out, i, lanes,
                    sample_uniform_lanes(sc.sampler, load_n<N>(key_pad), load_n<N>(index_pad), bit_length(all), depth, d));
    });
}

// The same for the points [0, n).
inline void fill_uniforms(const PathScratch& sc, size_t n, int depth, RandomDim d, float* out) {
    fill_uniforms(sc, 0, n, depth, d, out);
}

}  // namespace render_detail
PATINA_END_TARGET
