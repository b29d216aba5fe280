// The conductor material: anisotropic GGX (x along the tangent) with the complex index of
// refraction eta + i k per channel, scaled by `tint`; sampled by the normals visible from v.
#pragma once

#include <algorithm>
#include <optional>

#include "fit/microfacet.h"
#include "render/materials/ggx_aniso.h"

namespace patina {

struct Conductor {
    float alpha_x = 0.1f, alpha_y = 0.1f;
    float eta[3] = {1, 1, 1}, k[3] = {0, 0, 0};
    float tint[3] = {1, 1, 1};
    static constexpr bool picks_lobe = false;
    static constexpr bool transmits = false;
    std::optional<float> reflection_alpha() const { return std::min(alpha_x, alpha_y); }
    float highlight_alpha() const { return std::max(alpha_x, alpha_y); }
};

}  // namespace patina

PATINA_BEGIN_TARGET
namespace materials {

template <class F>
PATINA_INLINE Vec3<F> eval(const Conductor& m, const Vec3<F>& l, const Vec3<F>& v, F) {
    const F ax(m.alpha_x), ay(m.alpha_y);
    const Vec3<F> h = microfacet::half_vector(l, v);
    const F dg = ggx_aniso::d(h, ax, ay) * ggx_aniso::g2(l, v, ax, ay);
    const F cos_d = microfacet::mean_cos_d(l, v, h);
    F c[3];
    for (int ch = 0; ch < 3; ++ch)
        c[ch] = F(m.tint[ch]) * microfacet::microfacet_value(
                                    l, v, dg, F(1.0f), microfacet::fresnel_conductor(cos_d, F(m.eta[ch]), F(m.k[ch])));
    return Vec3<F>{c[0], c[1], c[2]};
}

template <class F>
PATINA_INLINE F pdf(const Conductor& m, const Vec3<F>& l, const Vec3<F>& v, F) {
    return ggx_aniso::pdf(v, l, F(m.alpha_x), F(m.alpha_y));
}

template <class F>
PATINA_INLINE Vec3<F> sample(const Conductor& m, const Vec3<F>& v, F, F u1, F u2, F) {
    return ggx_aniso::sample_reflection(v, u1, u2, F(m.alpha_x), F(m.alpha_y));
}

}  // namespace materials
PATINA_END_TARGET
