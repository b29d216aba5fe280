// A luminaire's candela towards N unit directions from it (render/lighting/direct_source.h):
// a point's constant, a spot's smoothstep cone, a goniometric luminaire's candela table by
// photometric type C or B. The arithmetic is the renderer's (render/lights/delta_intensity_impl.h:
// its cone, its angles by the same fast inverse trigonometry, its table through the same
// bilinear grid2_w::eval) on the lighting calculation's own description of the luminaire, so
// the lux of the lighting calculations and the light of a render agree.
#pragma once

#include <algorithm>

#include "core/constants.h"
#include "core/simd/fastmath.h"
#include "core/simd/kernel_width.h"
#include "render/lighting/direct_source.h"
#include "render/lights/grid2_impl.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// The component of the directions along a unit axis.
PATINA_INLINE F along(const V3& d, const float* axis) {
    return d.x * F(axis[0]) + d.y * F(axis[1]) + d.z * F(axis[2]);
}

PATINA_INLINE F spot_cone(const DirectSource& s, const V3& out) {
    const F t = clamp((along(out, s.axis) - F(s.cos_outer)) / F(std::max(s.cos_inner - s.cos_outer, 1e-6f)),
                      F(0.0f), F(1.0f));
    return t * t * nmadd(F(2.0f), t, F(3.0f));  // smoothstep
}

PATINA_INLINE F candela_table(const DirectSource& s, const V3& out) {
    const F x = along(out, s.axis_x), y = along(out, s.axis_y), z = along(out, s.axis_z);
    if (s.type_b) {
        // type B (docs/luminaires.md): H = asin(-x) within the plane, V = atan2(y, z) about x
        return grid2_w::eval<N>(s.candela, fast_asin(clamp(-x, F(-1.0f), F(1.0f))), fast_atan2(y, z));
    }
    // type C: gamma from the nadir (-axis_z), C from axis_x towards axis_y
    const F gamma = fast_acos(clamp(-z, F(-1.0f), F(1.0f)));
    F c = fast_atan2(y, x);
    c = select(c < F(0.0f), c + F(2.0f * kPi), c);
    return grid2_w::eval<N>(s.candela, c, gamma);
}

// `out`: unit, from the luminaire.
PATINA_INLINE F source_candela(const DirectSource& s, const V3& out) {
    switch (s.kind) {
        case SourceKind::Spot: return F(s.scale) * spot_cone(s, out);
        case SourceKind::Goniometric: return F(s.scale) * candela_table(s, out);
        default: return F(s.scale);
    }
}

}  // namespace render_detail
PATINA_END_TARGET
