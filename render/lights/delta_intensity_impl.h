// A delta light's relative intensity towards a direction, W directions at a time: 1 for a
// point light, the smooth cone of a spot, the candela table of a goniometric luminaire.
// Light sampling evaluates it N points at a time (the sample's radiance); the light
// selection one point at a time (W = 1, what selection_probability does) and N points at a
// time (sample_lights). The same function at every width gives every lane the same bits,
// so a point's selection probability is the same whether its pick or an MIS weight asks.
#pragma once

#include <algorithm>
#include <type_traits>

#include "core/constants.h"
#include "core/simd/fastmath.h"
#include "core/simd/kernel_width.h"
#include "render/lights/grid2_impl.h"
#include "render/scene.h"

PATINA_BEGIN_TARGET
namespace render_detail {

// `out`: unit, from the light.
template <int W>
PATINA_INLINE vfloat<W> relative_intensity(const PointLight&, const Vec3<vfloat<W>>&) {
    return vfloat<W>(1.0f);
}

template <int W>
PATINA_INLINE vfloat<W> relative_intensity(const SpotLight& l, const Vec3<vfloat<W>>& out) {
    using FW = vfloat<W>;
    const FW c = out.x * FW(l.direction[0]) + out.y * FW(l.direction[1]) + out.z * FW(l.direction[2]);
    const FW t = clamp((c - FW(l.cos_outer)) / FW(std::max(l.cos_inner - l.cos_outer, 1e-6f)), FW(0.0f), FW(1.0f));
    return t * t * nmadd(FW(2.0f), t, FW(3.0f));  // smoothstep
}

template <int W>
PATINA_INLINE vfloat<W> relative_intensity(const GoniometricLight& l, const Vec3<vfloat<W>>& out) {
    using FW = vfloat<W>;
    const FW x = out.x * FW(l.axis_x[0]) + out.y * FW(l.axis_x[1]) + out.z * FW(l.axis_x[2]);
    const FW y = out.x * FW(l.axis_y[0]) + out.y * FW(l.axis_y[1]) + out.z * FW(l.axis_y[2]);
    const FW z = out.x * FW(l.axis_z[0]) + out.y * FW(l.axis_z[1]) + out.z * FW(l.axis_z[2]);
    if (l.type_b) {
        // type B (docs/luminaires.md): H = asin(-x) within the plane, V = atan2(y, z) about x
        return grid2_w::eval<W>(l.candela, fast_asin(clamp(-x, FW(-1.0f), FW(1.0f))), fast_atan2(y, z));
    }
    // photometric type C: gamma from the nadir (-axis_z), C from axis_x towards axis_y
    const FW gamma = fast_acos(clamp(-z, FW(-1.0f), FW(1.0f)));
    FW c = fast_atan2(y, x);
    c = select(c < FW(0.0f), c + FW(2.0f * kPi), c);
    return grid2_w::eval<W>(l.candela, c, gamma);
}

// Any light's, 1 for those not of one point (never asked).
template <int W>
PATINA_INLINE vfloat<W> delta_intensity(const Light& l, const Vec3<vfloat<W>>& out) {
    return visit_kind(l, [&](const auto& kind) {
        if constexpr (std::decay_t<decltype(kind)>::is_delta) return relative_intensity<W>(kind, out);
        else return vfloat<W>(1.0f);
    });
}

}  // namespace render_detail
PATINA_END_TARGET
