// What a sensor takes of the illuminance E_n = I / d^2 on a plane normal to the light, N
// sensors at a time (render/lighting/illuminance_sensors.h; the definitions are
// python/patina/lighting/sensors.py's). Planar: cos(incidence) on the lit side. EN 13201-3's
// vertical cylinders, with y up: a full cylinder's mean sin(eps) / pi, a half-cylinder facing f
// sin(eps) (1 + cos(alpha)) / pi, eps the incidence from the vertical and alpha the horizontal
// angle between the light and f; sin(eps) cos(alpha) is the light's horizontal part along f,
// so the half-cylinder's is (sin(eps) + h . f) / pi with no division.
#pragma once

#include "core/constants.h"
#include "core/simd/kernel_width.h"
#include "render/lighting/illuminance_sensors.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// `towards`: unit, from the sensors to the light; `normal`: the sensors' normals (planar) or
// facings (semi-cylindrical).
PATINA_INLINE F sensor_response(SensorKind kind, const V3& towards, const V3& normal) {
    if (kind == SensorKind::Planar) return max(dot(towards, normal), F(0.0f));
    const F sin_eps = sqrt_exact(towards.x * towards.x + towards.z * towards.z);
    if (kind == SensorKind::Cylindrical) return sin_eps * F(kInvPi);
    const F along_facing = towards.x * normal.x + towards.z * normal.z;
    return max(sin_eps + along_facing, F(0.0f)) * F(kInvPi);
}

}  // namespace render_detail
PATINA_END_TARGET
