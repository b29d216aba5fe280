// The point light: an intensity (W/sr, RGB) from one position, the same in every direction.
#pragma once

#include "render/lights/light_selection.h"

namespace patina {

struct PointLight {
    float position[3] = {0, 0, 0};
    float intensity[3] = {1, 1, 1};
    static constexpr bool is_delta = true;
    static constexpr bool at_infinity = false;
    LightSelection selection(float small2, const float*) const {
        return delta_selection(position, intensity, small2);
    }
};

}  // namespace patina
