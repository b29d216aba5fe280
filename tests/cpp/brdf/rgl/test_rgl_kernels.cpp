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

using namespace patina;

namespace {

// A warp's arrays as rgl_warp.Interpolant2D(warp=True) makes them, from positive densities.
struct WarpArrays {
    std::vector<float> data, marginal, conditional;
};

WarpArrays make_warp(const std::vector<double>& density, int slices, int height, int width) {
    WarpArrays w;
    for (int s = 0; s < slices; ++s) {
        const double* d = density.data() + size_t(s) * height * width;
        std::vector<double> conditional(size_t(height) * width, 0.0), marginal(height, 0.0);
        for (int r = 0; r < height; ++r)
            for (int c = 1; c < width; ++c)
                conditional[r * width + c] =
                    conditional[r * width + c - 1] + 0.5 * (d[r * width + c] + d[r * width + c - 1]);
        for (int r = 1; r < height; ++r)
            marginal[r] = marginal[r - 1] + 0.5 * (conditional[r * width + width - 1] + conditional[(r - 1) * width + width - 1]);
        const double norm = 1.0 / marginal[height - 1];
        for (int i = 0; i < height * width; ++i) {
            w.data.push_back(float(d[i] * norm));
            w.conditional.push_back(float(conditional[i] * norm));
        }
        for (int r = 0; r < height; ++r) w.marginal.push_back(float(marginal[r] * norm));
    }
    return w;
}

std::vector<double> positive(std::mt19937& rng, size_t n) {
    std::uniform_real_distribution<double> u(0.05, 1.0);
    std::vector<double> v(n);
    for (double& x : v) x = u(rng);
    return v;
}

// A material of random positive grids: isotropic (one phi_i) or anisotropic over 360 / reduction degrees.
struct Material {
    std::vector<float> theta_i, phi_i, ndf, sigma, values;
    WarpArrays vndf, luminance;
    RglView view;

    Material(bool isotropic, int reduction) {
        std::mt19937 rng(isotropic ? 7 : 11 + reduction);
        for (int t = 0; t < 6; ++t) theta_i.push_back(float(t * 0.28));
        if (isotropic) phi_i = {0.0f};
        else
            for (int p = 0; p < 5; ++p) phi_i.push_back(float(-kPiDouble + p * 2 * kPiDouble / reduction / 4));
        const int slices = int(theta_i.size() * phi_i.size());
        for (double x : positive(rng, 8 * 12)) ndf.push_back(float(x));
        for (double x : positive(rng, 6 * 10)) sigma.push_back(float(x + 0.5));
        for (double x : positive(rng, size_t(slices) * kRglChannels * 9 * 11)) values.push_back(float(x - 0.1));
        vndf = make_warp(positive(rng, size_t(slices) * 10 * 14), slices, 10, 14);
        luminance = make_warp(positive(rng, size_t(slices) * 9 * 11), slices, 9, 11);
        view.theta_i = theta_i.data();
        view.phi_i = phi_i.data();
        view.theta_count = int(theta_i.size());
        view.phi_count = int(phi_i.size());
        view.ndf = {ndf.data(), 8, 12};
        view.sigma = {sigma.data(), 6, 10};
        view.values = {values.data(), 9, 11};
        view.vndf = {vndf.data.data(), vndf.marginal.data(), vndf.conditional.data(), 10, 14};
        view.luminance = {luminance.data.data(), luminance.marginal.data(), luminance.conditional.data(), 9, 11};
        view.isotropic = isotropic;
        view.jacobian = true;
        view.reduction = reduction;
    }
};

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
