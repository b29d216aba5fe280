// The RGL evaluator and pdf: widths 4, 8 and 16 bit-identical to width 1, lane by lane, on
// coherent and random pairs, isotropic and anisotropic (reduced) materials; the sampler's
// pdf against the pdf kernel's, and its directions above the horizon; its widths likewise
// bit-identical to width 1. (Accuracy against
// the double-precision reference is tested from Python: tests/python/table/formats/.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "brdf/rgl/rgl_kernels.h"
#include "core/constants.h"
#include "core/cpu.h"
#include "tests/cpp/brdf/rgl/rgl_test_material.h"

using namespace patina;
using Material = patina::test::RglTestMaterial;

namespace {

void push_direction(std::vector<float>& d, double theta, double phi) {
    d.push_back(float(std::sin(theta) * std::cos(phi)));
    d.push_back(float(std::sin(theta) * std::sin(phi)));
    d.push_back(float(std::cos(theta)));
}

// Random pairs over the sphere (some below the horizon), or neighbouring pairs swept slowly,
// as a row of pixels gives them; an odd count, so the last block is partial.
void make_pairs(bool coherent, std::vector<float>& wi, std::vector<float>& wo) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int n = 1001;
    for (int k = 0; k < n; ++k) {
        if (coherent) {
            push_direction(wi, 0.6 + 0.3 * k / n, 0.4 + 0.2 * k / n);
            push_direction(wo, 0.3 + 0.5 * k / n, 2.9 + 0.3 * k / n);
        } else {
            push_direction(wi, std::acos(2 * u(rng) - 1), 2 * kPiDouble * u(rng));
            push_direction(wo, std::acos(2 * u(rng) - 1), 2 * kPiDouble * u(rng));
        }
    }
}

class RglLanes : public ::testing::TestWithParam<int> {};

void expect_lanes_match_width_1(const Material& m, bool coherent, int width) {
    std::vector<float> wi, wo;
    make_pairs(coherent, wi, wo);
    const size_t n = wi.size() / 3;
    std::vector<float> ref(3 * n), out(3 * n), ref_pdf(n), pdf(n);
    rgl_eval_batch(m.view, wi.data(), wo.data(), ref.data(), n, 1, 1);
    rgl_eval_batch(m.view, wi.data(), wo.data(), out.data(), n, width, 1);
    rgl_pdf_batch(m.view, wi.data(), wo.data(), ref_pdf.data(), n, 1, 1);
    rgl_pdf_batch(m.view, wi.data(), wo.data(), pdf.data(), n, width, 1);
    int nonzero = 0;
    for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) ASSERT_EQ(std::memcmp(&ref[3 * i + c], &out[3 * i + c], 4), 0) << "pair " << i;
        ASSERT_EQ(std::memcmp(&ref_pdf[i], &pdf[i], 4), 0) << "pdf of pair " << i;
        nonzero += ref[3 * i] > 0.0f;
        ASSERT_TRUE(std::isfinite(ref[3 * i]) && std::isfinite(ref_pdf[i])) << "pair " << i;
    }
    EXPECT_GT(nonzero, int(n / 5));  // the test compares real values, not zeros
}

TEST_P(RglLanes, IsotropicMatchesWidth1) {
    if (!width_supported(GetParam())) GTEST_SKIP() << "width not supported on this CPU";
    const Material m(true, 1);
    expect_lanes_match_width_1(m, true, GetParam());
    expect_lanes_match_width_1(m, false, GetParam());
}

TEST_P(RglLanes, AnisotropicMatchesWidth1) {
    if (!width_supported(GetParam())) GTEST_SKIP() << "width not supported on this CPU";
    for (int reduction : {1, 2, 4}) {
        const Material m(false, reduction);
        expect_lanes_match_width_1(m, true, GetParam());
        expect_lanes_match_width_1(m, false, GetParam());
    }
}

INSTANTIATE_TEST_SUITE_P(Widths, RglLanes, ::testing::Values(4, 8, 16));

// Sampled directions and pdfs for random incident directions (a few below the horizon).
struct Samples {
    std::vector<float> wi, wo, pdf;
};

Samples sample(const Material& m, int width) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const size_t n = 999;
    Samples s;
    std::vector<float> u1(n), u2(n);
    for (size_t k = 0; k < n; ++k) {
        push_direction(s.wi, 1.65 * u(rng), 2 * kPiDouble * u(rng));
        u1[k] = u(rng);
        u2[k] = u(rng);
    }
    s.wo.resize(3 * n);
    s.pdf.resize(n);
    rgl_sample_batch(m.view, s.wi.data(), u1.data(), u2.data(), s.wo.data(), s.pdf.data(), n, width, 1);
    return s;
}

TEST_P(RglLanes, SamplesMatchWidth1) {
    if (!width_supported(GetParam())) GTEST_SKIP() << "width not supported on this CPU";
    for (bool isotropic : {true, false}) {
        const Material m(isotropic, isotropic ? 1 : 4);
        const Samples ref = sample(m, 1), wide = sample(m, GetParam());
        ASSERT_EQ(std::memcmp(ref.wo.data(), wide.wo.data(), 4 * ref.wo.size()), 0);
        ASSERT_EQ(std::memcmp(ref.pdf.data(), wide.pdf.data(), 4 * ref.pdf.size()), 0);
    }
}

TEST(RglSample, PdfMatchesThePdfKernel) {
    for (bool isotropic : {true, false}) {
        const Material m(isotropic, isotropic ? 1 : 2);
        const Samples s = sample(m, 1);
        const size_t n = s.pdf.size();
        std::vector<float> pdf(n);
        rgl_pdf_batch(m.view, s.wi.data(), s.wo.data(), pdf.data(), n, 1, 1);
        size_t above = 0, loose = 0;
        for (size_t k = 0; k < n; ++k) {
            if (s.pdf[k] == 0.0f) continue;
            ++above;
            const float* wo = &s.wo[3 * k];
            ASSERT_GT(wo[2], 0.0f);
            ASSERT_NEAR(wo[0] * wo[0] + wo[1] * wo[1] + wo[2] * wo[2], 1.0f, 1e-5f);
            // near the pole the pdf goes as 1 / u^3 of the square-root mapping, and the round
            // trip u -> m -> u in float keeps fewer digits there
            ASSERT_NEAR(pdf[k], s.pdf[k], 2e-2f * s.pdf[k]) << "sample " << k;
            loose += std::abs(pdf[k] - s.pdf[k]) > 2e-3f * s.pdf[k];
        }
        EXPECT_GT(above, n / 2);
        EXPECT_LT(loose, above / 100);
    }
}

}  // namespace
