// The emitter material: the triangles of an area light (a quad or an emissive mesh). It
// emits (render/integrators/emission_impl.h) and reflects nothing; its points are not shaded.
#pragma once

#include <optional>

#include "fit/microfacet.h"

namespace patina {

struct Emitter {
    int light = -1;  // the quad or triangles light whose triangles these are
    static constexpr bool picks_lobe = false;
    static constexpr bool transmits = false;
    std::optional<float> reflection_alpha() const { return std::nullopt; }
    float highlight_alpha() const { return kInfinity; }
};

}  // namespace patina

PATINA_BEGIN_TARGET
namespace materials {

template <class F>
PATINA_INLINE Vec3<F> eval(const Emitter&, const Vec3<F>&, const Vec3<F>&, F) {
    return Vec3<F>{F(0.0f), F(0.0f), F(0.0f)};
}

template <class F>
PATINA_INLINE F pdf(const Emitter&, const Vec3<F>&, const Vec3<F>&, F) {
    return F(0.0f);
}

template <class F>
PATINA_INLINE Vec3<F> sample(const Emitter&, const Vec3<F>&, F, F, F, F) {
    return Vec3<F>{F(0.0f), F(0.0f), F(1.0f)};
}

}  // namespace materials
PATINA_END_TARGET
