// The Lambert material: a diffuse reflector of RGB reflectance, cosine-weighted sampling.
#pragma once

#include <optional>

#include "fit/microfacet.h"

namespace patina {

struct Lambert {
    float reflectance[3] = {0.5f, 0.5f, 0.5f};
    static constexpr bool picks_lobe = false;
    static constexpr bool transmits = false;
    // a diffuse lobe: the radiance cache integrates it over texels of any size
    std::optional<float> reflection_alpha() const { return kInfinity; }
    float highlight_alpha() const { return kInfinity; }
};

}  // namespace patina

PATINA_BEGIN_TARGET
namespace materials {

template <class F>
PATINA_INLINE Vec3<F> eval(const Lambert& m, const Vec3<F>& l, const Vec3<F>& v, F) {
    return Vec3<F>{microfacet::lambert_eval(l, v, F(m.reflectance[0])), microfacet::lambert_eval(l, v, F(m.reflectance[1])),
                   microfacet::lambert_eval(l, v, F(m.reflectance[2]))};
}

template <class F>
PATINA_INLINE F pdf(const Lambert&, const Vec3<F>& l, const Vec3<F>& v, F) {
    return microfacet::lambert_pdf(v, l);
}

template <class F>
PATINA_INLINE Vec3<F> sample(const Lambert&, const Vec3<F>&, F, F u1, F u2, F) {
    return microfacet::lambert_sample(u1, u2);
}

}  // namespace materials
PATINA_END_TARGET
