// What the table and the fitted (mixture) materials share: their value is a measurement or
// a fit, scaled by an RGB tint, and they are importance sampled through a proxy -- a
// Lambert lobe picked with probability `diffuse`, else GGX of roughness `alpha`. The pdf is
// the proxy's, the value the material's own, so the estimate stays unbiased.
#pragma once

#include <cstddef>
#include <optional>

#include "fit/microfacet.h"
#include "render/materials/ggx_aniso.h"

namespace patina {

struct ProxySampling {
    float diffuse = 0.5f;
    float alpha = 0.2f;
};

// The part of the table and mixture kinds they share: a tint and the proxy.
struct SampledByProxy {
    float tint[3] = {1, 1, 1};
    ProxySampling proxy;
    static constexpr bool picks_lobe = true;  // the proxy's lobe
    static constexpr bool transmits = false;
    std::optional<float> reflection_alpha() const { return proxy.alpha; }
    float highlight_alpha() const { return kInfinity; }
};

// f (n rows of RGB) scaled by tint, skipped when the tint is white.
inline void apply_tint(const float tint[3], float* f, size_t n) {
    if (tint[0] == 1.0f && tint[1] == 1.0f && tint[2] == 1.0f) return;
    for (size_t i = 0; i < n; ++i)
        for (int ch = 0; ch < 3; ++ch) f[3 * i + ch] *= tint[ch];
}

}  // namespace patina

PATINA_BEGIN_TARGET
namespace materials {

template <class F>
PATINA_INLINE F pdf(const SampledByProxy& m, const Vec3<F>& l, const Vec3<F>& v, F) {
    const F pd(m.proxy.diffuse);
    return madd(pd, microfacet::lambert_pdf(v, l),
                (F(1.0f) - pd) * ggx_aniso::pdf(v, l, F(m.proxy.alpha), F(m.proxy.alpha)));
}

// The lobe picked by `pick` < diffuse, then l from (u1, u2).
template <class F>
PATINA_INLINE Vec3<F> sample(const SampledByProxy& m, const Vec3<F>& v, F pick, F u1, F u2, F) {
    const auto diffuse = pick < F(m.proxy.diffuse);
    const Vec3<F> dl = microfacet::lambert_sample(u1, u2);
    const Vec3<F> gl = ggx_aniso::sample_reflection(v, u1, u2, F(m.proxy.alpha), F(m.proxy.alpha));
    return Vec3<F>{select(diffuse, dl.x, gl.x), select(diffuse, dl.y, gl.y), select(diffuse, dl.z, gl.z)};
}

}  // namespace materials
PATINA_END_TARGET
