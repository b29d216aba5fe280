// The random numbers of many paths for one use at one bounce (rng.h's bounce_uniform),
// N keys at a time: what light selection, light sampling and BRDF sampling draw per point.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "core/simd/kernel_width.h"
#include "render/rng.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// out[q] = bounce_uniform(keys[q], depth, d).
inline void fill_uniforms(const int32_t* keys, size_t n, int depth, RandomDim d, float* out) {
    for_blocks(n, [&](size_t i, int lanes) {
        int32_t pad[N] = {};
        std::copy(keys + i, keys + i + lanes, pad);
        store_lanes(out, i, lanes, bounce_uniform_lanes(load_n<N>(pad), depth, d));
    });
}

}  // namespace render_detail
PATINA_END_TARGET
