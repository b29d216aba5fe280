// The table material: a measured RGB table (brdf/table.h) looked up by the table kernels,
// scaled by `tint`, sampled through its proxy (render/materials/proxy_sampling.h: its pdf
// and sample).
#pragma once

#include <cstddef>

#include "brdf/kernels.h"
#include "core/width_dispatch.h"
#include "render/materials/proxy_sampling.h"

namespace patina {

struct TableMaterial : SampledByProxy {
    const TableView* table = nullptr;
};

}  // namespace patina

PATINA_BEGIN_TARGET
namespace materials {

// f for n rows of (l, v), by the table kernels of SIMD width Width.
template <int Width>
inline void eval_rows(const TableMaterial& m, const float* l, const float* v, const float*, float* f, size_t n) {
    kernels_at_width<Width>(kernels_w1, kernels_w4, kernels_w8, kernels_w16).eval(*m.table, l, v, f, 0, n);
    apply_tint(m.tint, f, n);
}

}  // namespace materials
PATINA_END_TARGET
