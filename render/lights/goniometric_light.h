// The goniometric light (a luminaire of a photometric file): a candela table over (C, gamma)
// in radians, turned into RGB intensity by `rgb_per_candela` (W/sr per candela).
#pragma once

#include "render/lights/grid2.h"
#include "render/lights/light_selection.h"

namespace patina {

struct GoniometricLight {
    float position[3] = {0, 0, 0};
    // the luminaire's axes in the world (photometric type C: gamma = 0 along -axis_z, C = 0
    // along axis_x, C = 90 along axis_y)
    float axis_x[3] = {1, 0, 0}, axis_y[3] = {0, 1, 0}, axis_z[3] = {0, 0, 1};
    Grid2View candela{};
    bool type_b = false;  // photometric type B (beam along axis_z, axis_y up) instead of C
    float rgb_per_candela[3] = {1, 1, 1};
    static constexpr bool is_delta = true;
    static constexpr bool at_infinity = false;
    LightSelection selection(float small2, const float*) const {
        return delta_selection(position, rgb_per_candela, small2);
    }
};

}  // namespace patina
