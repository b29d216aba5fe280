// The constants every part shares: pi and its multiples, infinity, and the photometric
// ones (683 lm/W, the Rec. 709 luminance weights and the luminance they define). Each float
// constant is its value correctly rounded to float, written out rather than computed: 1 / pi
// rounded once is not float(1) / kPi.
#pragma once

#include <limits>

namespace patina {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kTwoPi = 6.28318530717958647692f;
constexpr float kHalfPi = 1.57079632679489661923f;
constexpr float kInvPi = 0.31830988618379067154f;
constexpr double kPiDouble = 3.14159265358979323846;  // for tables built in double (MERL, the environment's cdf)

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// The luminous efficacy that turns luminance-weighted watts into lumens (as the Python
// side's colour constants).
constexpr float kLumensPerWatt = 683.0f;

// Luminance Y of linear Rec. 709 / sRGB RGB, summed in T: float for the renderer's samples,
// double where weights are accumulated over a whole map.
constexpr double kLuminanceWeights[3] = {0.2126, 0.7152, 0.0722};
static_assert(float(kLuminanceWeights[0]) == 0.2126f && float(kLuminanceWeights[1]) == 0.7152f &&
                  float(kLuminanceWeights[2]) == 0.0722f,
              "the weights round to float as written in float");
template <class T = float>
constexpr T luminance(const float* rgb) {
    return T(kLuminanceWeights[0]) * rgb[0] + T(kLuminanceWeights[1]) * rgb[1] + T(kLuminanceWeights[2]) * rgb[2];
}

}  // namespace patina
