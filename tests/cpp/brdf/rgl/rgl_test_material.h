// A random RGL material for the tests of the RGL kernels (tests/cpp/brdf/rgl/) and of the
// renderer's RGL material (tests/cpp/render/materials/): positive random grids, its warps
// normalised as rgl_warp.Interpolant2D(warp=True) makes them, isotropic (one phi_i) or
// anisotropic over 360 / reduction degrees.
#pragma once

#include <random>
#include <vector>

#include "brdf/rgl/rgl_view.h"
#include "core/constants.h"

namespace patina::test {

// A warp's arrays as rgl_warp.Interpolant2D(warp=True) makes them, from positive densities.
struct WarpArrays {
    std::vector<float> data, marginal, conditional;
};

inline WarpArrays make_warp(const std::vector<double>& density, int slices, int height, int width) {
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

inline std::vector<double> positive(std::mt19937& rng, size_t n) {
    std::uniform_real_distribution<double> u(0.05, 1.0);
    std::vector<double> v(n);
    for (double& x : v) x = u(rng);
    return v;
}

struct RglTestMaterial {
    std::vector<float> theta_i, phi_i, ndf, sigma, values;
    WarpArrays vndf, luminance;
    RglView view;

    RglTestMaterial(bool isotropic, int reduction) {
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

}  // namespace patina::test
