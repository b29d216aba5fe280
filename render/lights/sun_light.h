// The sun: a disc of uniform radiance at infinity, `direction` towards its centre, sampled
// uniformly in its cone.
#pragma once

#include <algorithm>

#include "core/constants.h"
#include "render/lights/light_selection.h"

namespace patina {

struct SunLight {
    float direction[3] = {0, -1, 0};  // towards the sun (unit)
    float cos_sun = 1;                // cosine of the disc's angular radius...
    float one_minus_cos = 0;          // ...and 1 - that cosine, computed without cancellation
    float frame_t[3] = {1, 0, 0}, frame_b[3] = {0, 0, 1};  // a frame around `direction`
    float radiance[3] = {1, 1, 1};                          // W/(m^2 sr)
    static constexpr bool is_delta = false;
    static constexpr bool at_infinity = true;
    // uniform radiance over a cone of half-angle d: irradiance pi sin^2 d L facing it
    LightSelection selection(float small2, const float*) const {
        return {false, false,
                static_cast<float>(kPiDouble * one_minus_cos * (1 + double(cos_sun)) *
                                   std::max(0.0, luminance<double>(radiance))),
                {0, 0, 0}, small2};
    }
};

}  // namespace patina
