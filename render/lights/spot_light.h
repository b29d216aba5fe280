// The spot light: a point light's intensity (W/sr, RGB) within a cone along `direction`,
// full inside cos_inner, smoothly to none at cos_outer (render/lights/delta_intensity_impl.h).
#pragma once

#include "render/lights/light_selection.h"

namespace patina {

struct SpotLight {
    float position[3] = {0, 0, 0};
    float direction[3] = {0, -1, 0};  // the axis it shines along (unit)
    float cos_inner = 1, cos_outer = 0;
    float intensity[3] = {1, 1, 1};  // on the axis
    static constexpr bool is_delta = true;
    static constexpr bool at_infinity = false;
    LightSelection selection(float small2, const float*) const {
        return delta_selection(position, intensity, small2);
    }
};

}  // namespace patina
