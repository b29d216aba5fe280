// What the area lights (a quad, triangles) share: a uniform radiance over a surface of
// `area`, emitted on its normal's side or on both; sampled uniformly by area.
#pragma once

#include <algorithm>

#include "core/constants.h"
#include "render/lights/light_selection.h"

namespace patina {

struct AreaLight {
    float area = 4;
    float radiance[3] = {1, 1, 1};  // W/(m^2 sr)
    bool two_sided = false;
    static constexpr bool is_delta = false;
    static constexpr bool at_infinity = false;

    // Its flux (W of luminance), for its selection weight.
    double flux() const {
        return area * kPiDouble * std::max(0.0, luminance<double>(radiance)) * (two_sided ? 2 : 1);
    }
    // Weighed by flux over the distance to `center`, not below its own size.
    LightSelection selection_at(const float center[3], float small2) const {
        return {true, false, static_cast<float>(flux()), {center[0], center[1], center[2]},
                std::max(small2, static_cast<float>(area / kPiDouble))};
    }
};

}  // namespace patina
