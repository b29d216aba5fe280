// Inputs for SIMD tests: random sweeps plus the special values every op must survive.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace test_values {

inline std::vector<float> specials() {
    const float inf = std::numeric_limits<float>::infinity();
    const float den = std::numeric_limits<float>::denorm_min();
    return {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, -0.5f, den, -den, 1e-39f, -1e-39f,
            std::numeric_limits<float>::min(), std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
            inf, -inf, std::numeric_limits<float>::quiet_NaN(), std::nextafter(1.0f, 0.0f), std::nextafter(-1.0f, 0.0f),
            std::nextafter(0.5f, 1.0f), 2.0f, -2.0f};
}

inline std::vector<float> with_specials(std::vector<float> v) {
    for (float s : specials()) v.push_back(s);
    return v;
}

inline std::vector<float> uniform(size_t n, float lo, float hi, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> d(lo, hi);
    std::vector<float> v(n);
    for (auto& x : v) x = d(rng);
    return v;
}

// Magnitudes spread over many binades: 2^lo .. 2^hi.
inline std::vector<float> log_uniform(size_t n, float lo, float hi, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> d(lo, hi);
    std::vector<float> v(n);
    for (auto& x : v) x = std::exp2(d(rng));
    return v;
}

// Random signs and magnitudes over many binades, plus the specials, shuffled.
inline std::vector<float> mixed(size_t n, unsigned seed) {
    auto v = log_uniform(n, -30.0f, 30.0f, seed);
    std::mt19937 rng(seed + 1000);
    for (auto& x : v)
        if (rng() & 1) x = -x;
    auto s = specials();
    for (size_t i = 0; i < s.size() * 3; ++i) v.push_back(s[i % s.size()]);
    std::shuffle(v.begin(), v.end(), rng);
    return v;
}

}  // namespace test_values
