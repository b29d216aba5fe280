// A light's entry in the light selection (render/lights/selection_impl.h): shading points
// pick a light in proportion to its estimated irradiance there -- an area light's flux /
// (4 pi max(d^2, size^2)) (d to its centre), a delta light's intensity towards the point /
// max(d^2, size^2) (its spot cone or candela table included), an infinite one's (sun,
// environment) irradiance. Each light kind makes its own (its `selection`).
#pragma once

#include <algorithm>

#include "core/constants.h"

namespace patina {

struct LightSelection {
    bool local;
    bool delta;       // a point, spot or goniometric light: weighed by its intensity towards the point
    float weight;     // area: flux (W); delta: intensity (W/sr; goniometric: per candela);
                      // infinite: irradiance (W/m^2); all of luminance
    float center[3];
    float size2;      // local: a squared size below which distance does not count
};

// A delta light's (point, spot, goniometric): its intensity `rgb` (on its axis, or per candela).
inline LightSelection delta_selection(const float position[3], const float rgb[3], float small2) {
    return {true, true, static_cast<float>(std::max(0.0, luminance<double>(rgb))),
            {position[0], position[1], position[2]}, small2};
}

}  // namespace patina
