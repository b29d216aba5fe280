// The renderer's materials (render/materials/material_impl.h, here at width 1; the Python tests check
// that whole renders are bit-identical at widths 4 and 8; the RGL kind's lanes:
// rgl_material_lane_tests.h): each samples the density it
// reports (chi-square, on the whole sphere for glass), keeps energy (directional albedo
// by its own importance sampling <= 1), and a very smooth lobe's value and density agree.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#define PATINA_KERNEL_WIDTH 1
#include "render/materials/material_impl.h"
#include "tests/cpp/brdf/rgl/rgl_test_material.h"
#include "tests/cpp/sampling_test.h"

using namespace patina;
using patina::render_detail::material_eval;
using patina::render_detail::material_pdf;
using patina::render_detail::material_sample;
using sampling_test::sampling_p_value;
using sampling_test::uniforms;

namespace {

struct Batch {
    std::vector<float> v, eta, l, pdf;
};

// n samples of l for one view direction at angle theta (azimuth 0.3) from the normal.
Batch sample(const Material& m, double theta, float eta, size_t n, unsigned seed) {
    Batch b;
    const float dir[3] = {float(std::sin(theta) * std::cos(0.3)), float(std::sin(theta) * std::sin(0.3)),
                          float(std::cos(theta))};
    b.v.resize(3 * n);
    for (size_t i = 0; i < 3 * n; ++i) b.v[i] = dir[i % 3];
    b.eta.assign(n, eta);
    b.l.resize(3 * n);
    b.pdf.resize(n);
    const auto pick = uniforms(n, seed), u1 = uniforms(n, seed + 1), u2 = uniforms(n, seed + 2);
    material_sample(m, b.v.data(), b.eta.data(), pick.data(), u1.data(), u2.data(), b.l.data(), b.pdf.data(), n);
    return b;
}

double pdf_at(const Material& m, const Batch& b, float eta, float x, float y, float z) {
    const float l[3] = {x, y, z};
    float p;
    material_pdf(m, l, b.v.data(), &eta, &p, 1);
    return p;
}

// Mean of f |cos| / pdf over the samples (per channel): the directional albedo.
std::vector<double> albedo(const Material& m, const Batch& b) {
    const size_t n = b.pdf.size();
    std::vector<float> f(3 * n);
    material_eval(m, b.l.data(), b.v.data(), b.eta.data(), f.data(), n);
    std::vector<double> sum(3, 0.0);
    for (size_t i = 0; i < n; ++i)
        if (b.pdf[i] > 0)
            for (int c = 0; c < 3; ++c) sum[c] += f[3 * i + c] * std::abs(b.l[3 * i + 2]) / b.pdf[i];
    for (double& s : sum) s /= double(n);
    return sum;
}

Material conductor(float ax, float ay) {
    Conductor c;
    c.alpha_x = ax;
    c.alpha_y = ay;
    for (int ch = 0; ch < 3; ++ch) c.eta[ch] = 1.0f, c.k[ch] = 1e4f;  // |F| = 1: a white lobe
    Material m;
    m.model = c;
    return m;
}

template <class Kind>
Material material_of(const Kind& kind) {
    Material m;
    m.model = kind;
    return m;
}

Material glass(float alpha) {
    Dielectric d;
    d.alpha = alpha;
    Material m;
    m.model = d;
    return m;
}

}  // namespace

TEST(RenderMaterials, ConductorSamplesItsPdfAndKeepsEnergy) {
    for (auto [ax, ay] : {std::pair{0.1f, 0.1f}, std::pair{0.4f, 0.15f}}) {
        const Material m = conductor(ax, ay);
        for (double theta : {0.3, 1.2}) {
            auto draw = [&](size_t n) { return sample(m, theta, 1.0f, n, 21).l; };
            const Batch ref = sample(m, theta, 1.0f, 1, 21);
            auto pdf = [&](float x, float y, float z) { return pdf_at(m, ref, 1.0f, x, y, z); };
            EXPECT_GT(sampling_p_value(draw, pdf), 1e-3) << ax << " " << ay << " theta " << theta;
            const auto a = albedo(m, sample(m, theta, 1.0f, 200000, 31));
            EXPECT_LE(a[0], 1.0 + 2e-3) << ax << " " << ay << " theta " << theta;
            EXPECT_GT(a[0], 0.5);
        }
    }
}

TEST(RenderMaterials, GlassSamplesItsPdfOnBothSides) {
    // roughness wide enough for the bins: a narrow transmitted lobe near the pole varies too
    // fast within a bin for the midpoint quadrature of the expected counts
    for (float alpha : {0.2f, 0.4f})
        for (float eta : {1.5f, 1.0f / 1.5f})  // entering and leaving
            for (double theta : {0.2, 0.9, 1.4}) {
                const Material m = glass(alpha);
                auto draw = [&](size_t n) { return sample(m, theta, eta, n, 41).l; };
                const Batch ref = sample(m, theta, eta, 1, 41);
                auto pdf = [&](float x, float y, float z) { return pdf_at(m, ref, eta, x, y, z); };
                EXPECT_GT(sampling_p_value(draw, pdf, 500000, 24, 32, true), 1e-3)
                    << "alpha " << alpha << " eta " << eta << " theta " << theta;
            }
}

TEST(RenderMaterials, GlassKeepsEnergyAndIsExactWhenSmooth) {
    // Reflected + transmitted energy, counting transmitted radiance back at eta^2 (the
    // radiance scaling), is at most 1: exactly 1 for a smooth interface.
    for (float eta : {1.5f, 1.0f / 1.5f}) {
        for (double theta : {0.2, 0.9, 1.3}) {
            for (float alpha : {0.001f, 0.3f}) {
                const Material m = glass(alpha);
                const Batch b = sample(m, theta, eta, 200000, 51);
                std::vector<float> f(b.l.size());
                material_eval(m, b.l.data(), b.v.data(), b.eta.data(), f.data(), b.pdf.size());
                double energy = 0;
                for (size_t i = 0; i < b.pdf.size(); ++i) {
                    if (!(b.pdf[i] > 0)) continue;
                    const double scale = b.l[3 * i + 2] < 0 ? double(eta) * eta : 1.0;
                    energy += f[3 * i] * std::abs(b.l[3 * i + 2]) / b.pdf[i] * scale;
                }
                energy /= double(b.pdf.size());
                EXPECT_LE(energy, 1.0 + 2e-3) << "eta " << eta << " theta " << theta << " alpha " << alpha;
                if (alpha < 0.01f) {
                    EXPECT_NEAR(energy, 1.0, 2e-3) << "eta " << eta << " theta " << theta;
                }
            }
        }
    }
}

TEST(RenderMaterials, CoatOverLambertSamplesItsPdfAndKeepsEnergy) {
    Material m;
    Lambert white;
    white.reflectance[0] = white.reflectance[1] = white.reflectance[2] = 1.0f;
    m.model = white;
    m.albedo[0] = m.albedo[1] = m.albedo[2] = 1.0f;
    m.coat = ClearCoat{};
    m.coat->alpha = 0.15f;  // rough enough to bin; the smooth coat is the furnace tests' case
    for (double theta : {0.3, 1.2}) {
        auto draw = [&](size_t n) { return sample(m, theta, 1.0f, n, 61).l; };
        const Batch ref = sample(m, theta, 1.0f, 1, 61);
        auto pdf = [&](float x, float y, float z) { return pdf_at(m, ref, 1.0f, x, y, z); };
        EXPECT_GT(sampling_p_value(draw, pdf), 1e-3) << "theta " << theta;
        EXPECT_LE(albedo(m, sample(m, theta, 1.0f, 200000, 71))[0], 1.0 + 3e-3) << "theta " << theta;
    }
}

TEST(RenderMaterials, TableProxySamplesItsPdf) {
    // a Mixture (a fitted model) sampled through the Lambert + GGX proxy
    Mixture fit;
    fit.params.rho[0] = fit.params.rho[1] = fit.params.rho[2] = 0.3f;
    fit.params.lobes = 1;
    for (int c = 0; c < 3; ++c)
        fit.params.shape[0][c] = fit.params.shape_y[0][c] = 0.2f, fit.params.weight[0][c] = 0.04f;
    fit.proxy.diffuse = 0.4f;
    fit.proxy.alpha = 0.25f;
    Material m;
    m.model = fit;
    for (double theta : {0.3, 1.1}) {
        auto draw = [&](size_t n) { return sample(m, theta, 1.0f, n, 81).l; };
        const Batch ref = sample(m, theta, 1.0f, 1, 81);
        auto pdf = [&](float x, float y, float z) { return pdf_at(m, ref, 1.0f, x, y, z); };
        EXPECT_GT(sampling_p_value(draw, pdf), 1e-3) << "theta " << theta;
    }
}

// A random RGL file's VNDF shaped as a real file's: vanishing at the pole as the Jacobian of the
// square-root mapping, 2 pi^2 u sin(theta), does. Unshaped, the density of m grows as
// 1 / (u sin theta) there, too fast within a bin for the chi-square's midpoint quadrature.
void shape_like_a_vndf(test::RglTestMaterial& file) {
    RglWarpView& w = file.view.vndf;
    const int slices = file.view.theta_count * file.view.phi_count, cells = w.height * w.width;
    std::vector<double> density(size_t(slices) * cells);
    for (size_t i = 0; i < density.size(); ++i) {
        const double u = double(int(i % cells) % w.width) / (w.width - 1);
        density[i] = (1e-3 + file.vndf.data[i]) * u * std::sin(u * u * kPiDouble / 2);
    }
    file.vndf = test::make_warp(density, slices, w.height, w.width);
    w.data = file.vndf.data.data();
    w.marginal = file.vndf.marginal.data();
    w.conditional = file.vndf.conditional.data();
}

TEST(RenderMaterials, RglSamplesItsPdfAndKeepsItsValue) {
    // a random RGL file (its warps' own density, whatever the values): the renderer's RGL kind
    // draws by the warps, and a sample the warps drop (below the horizon) has neither density
    // nor value
    for (bool isotropic : {true, false}) {
        test::RglTestMaterial file(isotropic, isotropic ? 1 : 2);
        shape_like_a_vndf(file);
        RglMaterial rgl;
        rgl.rgl = &file.view;
        const Material m = material_of(rgl);
        for (double theta : {0.3, 1.1}) {
            auto draw = [&](size_t n) { return sample(m, theta, 1.0f, n, 91).l; };
            const Batch ref = sample(m, theta, 1.0f, 1, 91);
            auto pdf = [&](float x, float y, float z) { return pdf_at(m, ref, 1.0f, x, y, z); };
            EXPECT_GT(sampling_p_value(draw, pdf, 250000), 1e-3) << "isotropic " << isotropic << " theta " << theta;
            const Batch b = sample(m, theta, 1.0f, 4096, 93);
            std::vector<float> f(b.l.size());
            material_eval(m, b.l.data(), b.v.data(), b.eta.data(), f.data(), b.pdf.size());
            for (size_t i = 0; i < b.pdf.size(); ++i) {
                if (b.l[3 * i + 2] <= 0.0f) {
                    ASSERT_TRUE(b.pdf[i] == 0.0f && f[3 * i] == 0.0f) << "sample " << i;
                }
            }
        }
    }
}
