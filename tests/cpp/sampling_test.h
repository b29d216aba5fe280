// Sampling against a density: a chi-square test over (cos theta, phi) bins, as pbrt-v4 and
// Mitsuba 3 test their BSDF samplers. Shared by the lobe and the render-material tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

#include "core/constants.h"

namespace sampling_test {

using patina::kPiDouble;


// n uniforms in [0, 1) from a fixed seed.
inline std::vector<float> uniforms(size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> v(n);
    for (float& x : v) x = u(rng);
    return v;
}

// Upper tail probability of a chi-square statistic (Wilson-Hilferty normal approximation).
inline double chi2_tail(double chi2, int dof) {
    const double k = dof, z = (std::cbrt(chi2 / k) - (1 - 2 / (9 * k))) / std::sqrt(2 / (9 * k));
    return 0.5 * std::erfc(z / std::sqrt(2.0));
}

// Under AddressSanitizer (make check-sanitize) the test draws a fifth of the samples: the same
// sampler code and bins, run for memory and undefined-behaviour faults (over a hundred samples a
// bin still); the Release run (make test-cpp) keeps the full count and its power against a wrong pdf.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr size_t kSanitizerSampleShare = 5;
#else
inline constexpr size_t kSanitizerSampleShare = 1;
#endif

// The upper tail probability of sampled directions against a pdf, binned over (cos theta,
// phi) on the upper hemisphere, or over (theta, phi) on the whole sphere (uniform in theta,
// so a lobe about either pole still spans several bins). sample(n) returns n x 3
// directions, pdf(x, y, z) the density there. Samples the sampler drops (zero or non-unit
// directions) count nowhere, as the pdf gives them no mass.
template <class Sample, class Pdf>
double sampling_p_value(Sample sample, Pdf pdf, size_t n = 1000000, int nt = 24, int np = 48,
                        bool whole_sphere = false) {
    n /= kSanitizerSampleShare;
    const std::vector<float> wo = sample(n);
    // the bin coordinate: cos theta in [0, 1], or theta in [0, pi]
    auto coord = [&](double z) { return whole_sphere ? std::acos(std::clamp(z, -1.0, 1.0)) / kPiDouble : z; };
    std::vector<double> observed(nt * np, 0.0), expected(nt * np, 0.0);
    for (size_t i = 0; i < n; ++i) {
        const double z = wo[3 * i + 2];
        const double len2 = double(wo[3 * i]) * wo[3 * i] + double(wo[3 * i + 1]) * wo[3 * i + 1] + z * z;
        if (!(std::abs(len2 - 1) < 1e-3) || z == 0 || (!whole_sphere && !(z > 0))) continue;
        double phi = std::atan2(wo[3 * i + 1], wo[3 * i]);
        if (phi < 0) phi += 2 * kPiDouble;
        observed[std::min(nt - 1, int(coord(z) * nt)) * np + std::min(np - 1, int(phi / (2 * kPiDouble) * np))] += 1;
    }
    const int sub = 8;
    for (int a = 0; a < nt; ++a)
        for (int b = 0; b < np; ++b)
            for (int s = 0; s < sub; ++s)
                for (int t = 0; t < sub; ++t) {
                    const double c = (a + (s + 0.5) / sub) / nt, phi = 2 * kPiDouble * (b + (t + 0.5) / sub) / np;
                    // solid angle per unit of the bin coordinate: dz, or sin(theta) pi dc
                    const double z = whole_sphere ? std::cos(kPiDouble * c) : c;
                    const double jacobian = whole_sphere ? kPiDouble * std::sin(kPiDouble * c) : 1.0;
                    const double r = std::sqrt(std::max(0.0, 1 - z * z));
                    const double p = pdf(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
                    expected[a * np + b] += p * jacobian * (1.0 / nt) * (2 * kPiDouble / np) / (sub * sub) * double(n);
                }
    double chi2 = 0, pooled_obs = 0, pooled_exp = 0;
    int dof = 0;
    for (size_t k = 0; k < expected.size(); ++k) {
        if (expected[k] < 5) {
            pooled_obs += observed[k];
            pooled_exp += expected[k];
            continue;
        }
        chi2 += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
        ++dof;
    }
    if (pooled_exp >= 5) {
        chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
        ++dof;
    }
    return chi2_tail(chi2, dof - 1);
}

}  // namespace sampling_test
