// The mixture material: a fitted analytic model (fit/lobe_kernels.h) evaluated by the lobe
// kernels, scaled by `tint`, sampled through its proxy (render/materials/proxy_sampling.h:
// its pdf and sample).
#pragma once

#include <cstddef>

#include "core/width_dispatch.h"
#include "fit/lobe_kernels.h"
#include "render/materials/proxy_sampling.h"

namespace patina {

struct Mixture : SampledByProxy {
    MixtureParams params;
};

}  // namespace patina

PATINA_BEGIN_TARGET
namespace materials {

// f for n rows of (l, v), by the lobe kernels of SIMD width Width.
template <int Width>
inline void eval_rows(const Mixture& m, const float* l, const float* v, const float*, float* f, size_t n) {
    kernels_at_width<Width>(lobe_kernels_w1, lobe_kernels_w4, lobe_kernels_w8, lobe_kernels_w16)
        .eval_mixture(m.params, l, v, f, n);
    apply_tint(m.tint, f, n);
}

}  // namespace materials
PATINA_END_TARGET
