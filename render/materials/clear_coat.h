// The clear coat, a layer over any reflecting material (car paint): a GGX dielectric
// interface of index `eta` reflects F; the base is seen through it, dimmed by
// (1 - F(cos_l)) (1 - F(cos_v)) and coloured by `tint`. Roughness 0 (a smooth coat) is taken
// as alpha 1e-3.
#pragma once

#include <algorithm>

#include "fit/microfacet.h"
#include "render/materials/ggx_aniso.h"

namespace patina {

struct ClearCoat {
    float eta = 1.5f;
    float alpha = 1e-3f;
    float tint[3] = {1, 1, 1};
};

}  // namespace patina

PATINA_BEGIN_TARGET
namespace materials {

// The coat's GGX reflection with exact dielectric Fresnel (fit/microfacet.h's coat lobe),
// with D and G from render/materials/ggx_aniso.h: computed from the directions' components,
// they keep their precision for the nearly smooth coats of car paint, where D from
// cos(theta_h) near 1 would lose it (and no longer cancel against the sampling density).
template <class F>
PATINA_INLINE F coat_reflection(const Vec3<F>& l, const Vec3<F>& v, F alpha, F eta) {
    const Vec3<F> h = microfacet::half_vector(l, v);
    const F dg = ggx_aniso::d(h, alpha, alpha) * ggx_aniso::g2(l, v, alpha, alpha);
    return microfacet::microfacet_value(l, v, dg, F(1.0f),
                                        microfacet::fresnel_dielectric(microfacet::mean_cos_d(l, v, h), eta));
}

// The base's value `base` seen through the coat, plus the coat's own reflection.
template <class F>
PATINA_INLINE Vec3<F> over_coat(const ClearCoat& coat, const Vec3<F>& l, const Vec3<F>& v, const Vec3<F>& base) {
    const F eta(coat.eta);
    const F through = (F(1.0f) - microfacet::fresnel_dielectric(max(l.z, F(0.0f)), eta)) *
                      (F(1.0f) - microfacet::fresnel_dielectric(max(v.z, F(0.0f)), eta));
    const F spec = coat_reflection(l, v, F(coat.alpha), eta);
    return Vec3<F>{madd(base.x * F(coat.tint[0]), through, spec), madd(base.y * F(coat.tint[1]), through, spec),
                   madd(base.z * F(coat.tint[2]), through, spec)};
}

// The coat's probability of being sampled, from v alone (so sampling and pdf agree): its
// Fresnel reflectance against what the base reflects (the luminance of its albedo), kept in
// [0.1, 0.9].
template <class F>
PATINA_INLINE F coat_pick(const ClearCoat& coat, float base_luminance, F cos_v) {
    const F fr = microfacet::fresnel_dielectric(max(cos_v, F(0.0f)), F(coat.eta));
    return clamp(fr / (fr + (F(1.0f) - fr) * F(std::max(base_luminance, 1e-3f))), F(0.1f), F(0.9f));
}

// The coat's sampling density of l given v (its own lobe alone).
template <class F>
PATINA_INLINE F coat_pdf(const ClearCoat& coat, const Vec3<F>& l, const Vec3<F>& v) {
    return ggx_aniso::pdf(v, l, F(coat.alpha), F(coat.alpha));
}

template <class F>
PATINA_INLINE Vec3<F> coat_sample(const ClearCoat& coat, const Vec3<F>& v, F u1, F u2) {
    return ggx_aniso::sample_reflection(v, u1, u2, F(coat.alpha), F(coat.alpha));
}

}  // namespace materials
PATINA_END_TARGET
