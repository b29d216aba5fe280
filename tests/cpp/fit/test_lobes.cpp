// The analytic lobes: reciprocity, energy conservation, sampling against the pdf
// (a chi-square test, as pbrt-v4 and Mitsuba 3 do), wide widths against width 1.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/constants.h"
#include "core/cpu.h"
#include "fit/lobe_kernels.h"
#include "fit/microfacet.h"
#include "tests/cpp/sampling_test.h"

using namespace patina;
using sampling_test::sampling_p_value;
using sampling_test::uniforms;

namespace {

std::vector<float> hemisphere(size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<float> d;
    for (size_t i = 0; i < n; ++i) {
        const double z = u(rng), phi = 2 * kPiDouble * u(rng), r = std::sqrt(1 - z * z);
        d.insert(d.end(), {float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)});
    }
    return d;
}

MixtureParams mixture(float r, float g, float b, float alpha, float f0r, float f0g, float f0b,
                      LobeKind kind = LobeKind::GGX) {
    MixtureParams p;
    p.rho[0] = r;
    p.rho[1] = g;
    p.rho[2] = b;
    p.kind = kind;
    p.lobes = 1;
    p.shape[0][0] = p.shape[0][1] = p.shape[0][2] = alpha;
    p.shape_y[0][0] = p.shape_y[0][1] = p.shape_y[0][2] = alpha;
    p.weight[0][0] = f0r;
    p.weight[0][1] = f0g;
    p.weight[0][2] = f0b;
    return p;
}

std::vector<float> eval(const MixtureParams& p, const std::vector<float>& wi, const std::vector<float>& wo,
                        int width = 1) {
    std::vector<float> out(wi.size());
    lobe_kernels_for(width).eval_mixture(p, wi.data(), wo.data(), out.data(), wi.size() / 3);
    return out;
}

// Directional albedo of channel 0 at incidence theta by a midpoint rule over (cos theta_o, phi_o).
double quadrature_albedo(const MixtureParams& p, double theta, int nmu = 256, int nphi = 256) {
    std::vector<float> wi, wo;
    std::vector<double> weight;
    for (int a = 0; a < nmu; ++a)
        for (int b = 0; b < nphi; ++b) {
            const double mu = (a + 0.5) / nmu, phi = 2 * kPiDouble * (b + 0.5) / nphi, r = std::sqrt(1 - mu * mu);
            wi.insert(wi.end(), {float(std::sin(theta)), 0.0f, float(std::cos(theta))});
            wo.insert(wo.end(), {float(r * std::cos(phi)), float(r * std::sin(phi)), float(mu)});
            weight.push_back(mu * (1.0 / nmu) * (2 * kPiDouble / nphi));
        }
    const auto f = eval(p, wi, wo);
    double albedo = 0;
    for (size_t i = 0; i < weight.size(); ++i) albedo += f[3 * i] * weight[i];
    return albedo;
}

}  // namespace

TEST(Lobes, Reciprocal) {
    const auto wi = hemisphere(20000, 1), wo = hemisphere(20000, 2);
    for (float alpha : {0.05f, 0.2f, 0.6f}) {
        for (LobeKind kind : {LobeKind::GGX, LobeKind::Beckmann, LobeKind::BlinnPhong, LobeKind::AshikhminShirley}) {
            const float shape = kind == LobeKind::BlinnPhong || kind == LobeKind::AshikhminShirley ? 2.0f / (alpha * alpha) : alpha;
            const MixtureParams p = mixture(0.3f, 0.5f, 0.2f, shape, 0.04f, 0.5f, 0.9f, kind);
            const auto a = eval(p, wi, wo), b = eval(p, wo, wi);
            EXPECT_EQ(a, b) << "alpha " << alpha << " kind " << int(kind);  // symmetric expressions: bit for bit
        }
    }
}

TEST(Lobes, WideWidthsMatchScalar) {
    const auto wi = hemisphere(10007, 3), wo = hemisphere(10007, 4);
    const auto u1 = uniforms(10007, 5), u2 = uniforms(10007, 6);
    MixtureParams p = mixture(0.3f, 0.5f, 0.2f, 0.15f, 0.04f, 0.5f, 0.9f);
    p.lobes = 3;  // three lobes of each kind, one with a different shape per channel
    for (int c = 0; c < 3; ++c) {
        p.shape[1][c] = 0.4f;
        p.shape[2][c] = 0.05f + 0.02f * c;
    }
    for (int l = 1; l < 3; ++l)
        for (int c = 0; c < 3; ++c) p.weight[l][c] = 0.1f * float(l + c);
    const auto ref = eval(p, wi, wo, 1);
    for (LobeKind kind : {LobeKind::Beckmann, LobeKind::BlinnPhong}) {
        MixtureParams q = p;
        q.kind = kind;
        if (kind == LobeKind::BlinnPhong)
            for (auto& lobe : q.shape)
                for (float& s : lobe) s = s > 0 ? 2.0f / (s * s) : 1.0f;
        const auto r1 = eval(q, wi, wo, 1);
        for (int w : {4, 8, 16}) {
            if (width_supported(w)) {
                EXPECT_EQ(eval(q, wi, wo, w), r1) << "kind " << int(kind) << " width " << w;
            }
        }
    }
    std::vector<float> s1(wi.size()), p1(wi.size() / 3);
    lobe_kernels_w1().sample_lobe(LobeKind::GGX, 0.3f, wi.data(), u1.data(), u2.data(), s1.data(), p1.data(), p1.size());
    for (int w : {4, 8, 16}) {
        if (!width_supported(w)) continue;
        EXPECT_EQ(eval(p, wi, wo, w), ref) << "width " << w;
        std::vector<float> sw(wi.size()), pw(wi.size() / 3);
        lobe_kernels_for(w).sample_lobe(LobeKind::GGX, 0.3f, wi.data(), u1.data(), u2.data(), sw.data(), pw.data(), pw.size());
        EXPECT_EQ(sw, s1) << "width " << w;
        EXPECT_EQ(pw, p1) << "width " << w;
    }
}

// Three lobes of each new kind (anisotropic Ward and Ashikhmin-Shirley, Lafortune), with
// per-channel shapes and a coat: every wide width gives width 1's values bit for bit, and
// each mixture is reciprocal bit for bit.
TEST(Lobes, AnisotropicAndLafortuneMixturesMatchScalarAndAreReciprocal) {
    const auto wi = hemisphere(10007, 30), wo = hemisphere(10007, 31);
    struct Case {
        LobeKind kind;
        float x[3], y[3];  // shape and shape_y of lobe 0, 1, 2 (channel 0; the others vary)
    };
    const Case cases[] = {
        {LobeKind::Ward, {0.05f, 0.2f, 0.5f}, {0.3f, 0.06f, 0.5f}},
        {LobeKind::AshikhminShirley, {400.0f, 20.0f, 3.0f}, {30.0f, 900.0f, 3.0f}},
        {LobeKind::Lafortune, {60.0f, 6.0f, 1.5f}, {0.0f, 0.0f, 0.0f}},
    };
    const float c[3][3] = {{-1.1f, -0.9f, 1.0f}, {0.8f, 0.8f, 1.0f}, {0.0f, 0.0f, 0.7f}};  // forward, retro, normal
    for (const Case& k : cases) {
        for (bool coat : {false, true}) {
            MixtureParams p = mixture(0.3f, 0.5f, 0.2f, 0.0f, 0.0f, 0.0f, 0.0f, k.kind);
            p.lobes = 3;
            p.coat = coat;
            for (int l = 0; l < 3; ++l)
                for (int ch = 0; ch < 3; ++ch) {
                    p.shape[l][ch] = k.x[l] * (1.0f + 0.1f * ch);
                    p.shape_y[l][ch] = k.y[l] * (1.0f + 0.1f * ch);
                    p.weight[l][ch] = 0.05f + 0.1f * float(l + ch);
                    p.lafortune_c[l][ch] = c[l][ch];
                }
            const auto r1 = eval(p, wi, wo, 1);
            EXPECT_EQ(eval(p, wo, wi, 1), r1) << "kind " << int(k.kind) << " coat " << coat;
            for (float v : r1) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << "kind " << int(k.kind);
            for (int w : {4, 8, 16}) {
                if (width_supported(w)) {
                    EXPECT_EQ(eval(p, wi, wo, w), r1) << "kind " << int(k.kind) << " coat " << coat << " width " << w;
                }
            }
        }
    }
}

// The mixture's anisotropic lobes are the microfacet.h lobes with alpha_x / nu along the
// local x axis, and its Lafortune lobe is w (n + 2) / (2 pi) times lafortune_eval.
// GGX with Schlick Fresnel in double precision: the reference for the mixture's GGX lobe.
double ggx_reference(const float* a, const float* b, double alpha, double f0) {
    const double s[3] = {double(a[0]) + b[0], double(a[1]) + b[1], double(a[2]) + b[2]};
    const double len = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    const double c = s[2] / len, ci = a[2], co = b[2], a2 = alpha * alpha;
    if (!(ci > 0 && co > 0)) return 0;
    const double t = c * c * (a2 - 1) + 1, d = a2 / (kPiDouble * t * t);
    const double lambda_i = 0.5 * (std::sqrt(1 + a2 * (1 - ci * ci) / (ci * ci)) - 1);
    const double lambda_o = 0.5 * (std::sqrt(1 + a2 * (1 - co * co) / (co * co)) - 1);
    const double cos_d = (double(a[0]) * s[0] + double(a[1]) * s[1] + double(a[2]) * s[2]) / len;
    const double fresnel = f0 + (1 - f0) * std::pow(1 - cos_d, 5);
    return d / (1 + lambda_i + lambda_o) * fresnel / (4 * ci * co);
}

// The mixture evaluates each lobe's shape once for the three channels: GGX (in a one-division
// form, its D free of the cancellation of cos(theta_h) near 1) against double precision,
// Beckmann and Blinn-Phong against microfacet.h's per-channel functions.
TEST(Lobes, MixtureMicrofacetLobesMatchTheirModels) {
    const auto wi = hemisphere(4000, 34), wo = hemisphere(4000, 35);
    for (LobeKind kind : {LobeKind::GGX, LobeKind::Beckmann, LobeKind::BlinnPhong}) {
        for (float shape : {0.02f, 0.3f, 0.9f}) {
            const float s = kind == LobeKind::BlinnPhong ? 2.0f / (shape * shape) - 2.0f : shape;
            const MixtureParams p = mixture(0, 0, 0, s, 0.04f, 0.5f, 1.0f, kind);
            const auto f = eval(p, wi, wo);
            for (size_t i = 0; i < wi.size() / 3; ++i) {
                const patina::Vec3f a{wi[3 * i], wi[3 * i + 1], wi[3 * i + 2]};
                const patina::Vec3f b{wo[3 * i], wo[3 * i + 1], wo[3 * i + 2]};
                for (int c = 0; c < 3; ++c) {
                    const float f0 = c == 0 ? 0.04f : c == 1 ? 0.5f : 1.0f;
                    if (kind == LobeKind::GGX) {
                        const double ref = ggx_reference(&wi[3 * i], &wo[3 * i], s, f0);
                        ASSERT_NEAR(f[3 * i + c], ref, 2e-5 * ref + 1e-30) << "shape " << s << " pair " << i;
                        continue;
                    }
                    const float ref = kind == LobeKind::Beckmann ? patina::microfacet::beckmann_eval(a, b, s, f0)
                                                                 : patina::microfacet::blinn_phong_eval(a, b, s, f0);
                    ASSERT_NEAR(f[3 * i + c], ref, 2e-5f * ref + 1e-30f)
                        << "kind " << int(kind) << " shape " << s << " pair " << i << " channel " << c;
                }
            }
        }
    }
}

TEST(Lobes, MixtureLobesAreTheModelsOfMicrofacetH) {
    using patina::microfacet::ashikhmin_shirley_eval;
    using patina::kInvPi;
    using patina::microfacet::lafortune_eval;
    using patina::microfacet::ward_eval;
    const auto wi = hemisphere(2000, 32), wo = hemisphere(2000, 33);
    MixtureParams ward = mixture(0, 0, 0, 0.1f, 0.3f, 0.3f, 0.3f, LobeKind::Ward);
    ward.shape_y[0][0] = ward.shape_y[0][1] = ward.shape_y[0][2] = 0.35f;
    MixtureParams as = mixture(0, 0, 0, 300.0f, 0.05f, 0.05f, 0.05f, LobeKind::AshikhminShirley);
    as.shape_y[0][0] = as.shape_y[0][1] = as.shape_y[0][2] = 15.0f;
    MixtureParams laf = mixture(0, 0, 0, 25.0f, 0.4f, 0.4f, 0.4f, LobeKind::Lafortune);
    laf.lafortune_c[0][0] = -1.2f;
    laf.lafortune_c[0][1] = -0.7f;
    laf.lafortune_c[0][2] = 0.9f;
    const auto fw = eval(ward, wi, wo), fa = eval(as, wi, wo), fl = eval(laf, wi, wo);
    for (size_t i = 0; i < wi.size() / 3; ++i) {
        const patina::Vec3f a{wi[3 * i], wi[3 * i + 1], wi[3 * i + 2]};
        const patina::Vec3f b{wo[3 * i], wo[3 * i + 1], wo[3 * i + 2]};
        ASSERT_FLOAT_EQ(fw[3 * i], ward_eval(a, b, 0.1f, 0.35f, 0.3f));
        ASSERT_FLOAT_EQ(fa[3 * i], ashikhmin_shirley_eval(a, b, 300.0f, 15.0f, 0.05f));
        ASSERT_FLOAT_EQ(fl[3 * i], lafortune_eval(a, b, -1.2f, -0.7f, 0.9f, 25.0f, 0.4f * 27.0f * (0.5f * kInvPi)));
    }
}

// Directional albedo by importance sampling the GGX lobe: white Fresnel (f0 = 1) loses
// energy to masking, never gains it; a white Lambert gives 1.
TEST(Lobes, EnergyIsConserved) {
    const size_t n = 400000;
    const auto u1 = uniforms(n, 7), u2 = uniforms(n, 8);
    for (float alpha : {0.02f, 0.1f, 0.3f, 0.7f, 1.0f}) {
        for (double theta : {0.0, 0.5, 1.0, 1.4}) {
            std::vector<float> wi;
            for (size_t i = 0; i < n; ++i)
                wi.insert(wi.end(), {float(std::sin(theta)), 0.0f, float(std::cos(theta))});
            std::vector<float> wo(3 * n), pdf(n);
            lobe_kernels_w1().sample_lobe(LobeKind::GGX, alpha, wi.data(), u1.data(), u2.data(), wo.data(), pdf.data(), n);
            const auto f = eval(mixture(0, 0, 0, alpha, 1, 1, 1), wi, wo);
            double sum = 0;
            for (size_t i = 0; i < n; ++i)
                if (pdf[i] > 0 && wo[3 * i + 2] > 0) sum += f[3 * i] * wo[3 * i + 2] / pdf[i];
            const double albedo = sum / n;
            EXPECT_LE(albedo, 1.0 + 3e-3) << "alpha " << alpha << " theta " << theta;
            EXPECT_GT(albedo, 0.3) << "alpha " << alpha << " theta " << theta;
        }
    }
    std::vector<float> wo(3 * n), pdf(n), wi;
    lobe_kernels_w1().sample_lambert(u1.data(), u2.data(), wo.data(), pdf.data(), n);
    for (size_t i = 0; i < n; ++i) wi.insert(wi.end(), {0.3f, 0.0f, 0.9539392f});
    const auto f = eval(mixture(1, 1, 1, 0.5f, 0, 0, 0), wi, wo);
    double sum = 0;
    for (size_t i = 0; i < n; ++i) sum += (f[3 * i] - 0.0) * wo[3 * i + 2] / pdf[i];
    // f includes the GGX lobe with f0 = 0, which Schlick makes slightly positive at grazing
    EXPECT_NEAR(sum / n, 1.0, 0.02);
}

// Fresnel terms against textbook values (width 1; the wide paths run the same code).
TEST(Lobes, FresnelReferenceValues) {
    using patina::microfacet::fresnel_conductor;
    using patina::microfacet::fresnel_dielectric;
    using patina::microfacet::fresnel_schlick;
    // glass, eta 1.5: ((1 - 1.5) / (1 + 1.5))^2 = 0.04 at normal incidence
    EXPECT_NEAR(fresnel_dielectric(1.0f, 1.5f), 0.04f, 1e-6f);
    // Brewster's angle, atan(1.5): the p-polarised part vanishes, R = Rs / 2
    const float cb = std::cos(std::atan(1.5f));
    const double sb = std::sin(std::atan(1.5)), st = sb / 1.5, ct = std::sqrt(1 - st * st);
    const double rs = (cb - 1.5 * ct) / (cb + 1.5 * ct);
    EXPECT_NEAR(fresnel_dielectric(cb, 1.5f), 0.5 * rs * rs, 1e-6);
    // grazing: everything is reflected; from inside beyond the critical angle too
    EXPECT_NEAR(fresnel_dielectric(0.0f, 1.5f), 1.0f, 1e-6f);
    EXPECT_EQ(fresnel_dielectric(0.3f, 1.0f / 1.5f), 1.0f);
    // conductor at normal incidence: ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2); gold-ish n 0.2, k 3.6
    const double n = 0.2, k = 3.6, r0 = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
    EXPECT_NEAR(fresnel_conductor(1.0f, 0.2f, 3.6f), r0, 1e-5);
    EXPECT_NEAR(fresnel_conductor(1e-4f, 0.2f, 3.6f), 1.0f, 1e-3f);
    // k = 0: the conductor formula is the dielectric one
    for (float c : {0.2f, 0.5f, 0.9f}) EXPECT_NEAR(fresnel_conductor(c, 1.5f, 0.0f), fresnel_dielectric(c, 1.5f), 1e-5f);
    // Schlick: f0 at normal incidence, 1 at grazing
    EXPECT_FLOAT_EQ(fresnel_schlick(0.04f, 1.0f), 0.04f);
    EXPECT_FLOAT_EQ(fresnel_schlick(0.04f, 0.0f), 1.0f);
}

// Beckmann and Blinn-Phong lobes keep energy: albedo by a dense quadrature over the
// outgoing hemisphere stays at or below 1 for the white lobe alone.
TEST(Lobes, AllKindsConserveEnergy) {
    for (LobeKind kind : {LobeKind::GGX, LobeKind::Beckmann, LobeKind::BlinnPhong, LobeKind::AshikhminShirley}) {
        for (float alpha : {0.1f, 0.3f, 0.8f}) {
            const bool exponent = kind == LobeKind::BlinnPhong || kind == LobeKind::AshikhminShirley;
            const float shape = exponent ? 2.0f / (alpha * alpha) - 2.0f : alpha;
            for (double theta : {0.0, 0.7, 1.3}) {
                const double albedo = quadrature_albedo(mixture(0, 0, 0, shape, 1, 1, 1, kind), theta);
                EXPECT_LE(albedo, 1.02) << "kind " << int(kind) << " alpha " << alpha << " theta " << theta;
                EXPECT_GT(albedo, 0.2) << "kind " << int(kind) << " alpha " << alpha << " theta " << theta;
            }
        }
    }
}


TEST(Lobes, WardIsReciprocalKeepsEnergyAndSamplesItsPdf) {
    using patina::microfacet::ward_pdf;
    const size_t n = 1000000;
    const auto u1 = uniforms(n, 11), u2 = uniforms(n, 12);
    for (auto [ax, ay] : {std::pair{0.1f, 0.1f}, std::pair{0.3f, 0.08f}, std::pair{0.5f, 0.5f}}) {
        for (double theta : {0.2, 1.0}) {
            const float w1[3] = {float(std::sin(theta) * 0.8), float(std::sin(theta) * 0.6), float(std::cos(theta))};
            auto sample = [&](size_t m) {
                std::vector<float> wi, wo(3 * m), pdf(m);
                for (size_t i = 0; i < m; ++i) wi.insert(wi.end(), w1, w1 + 3);
                lobe_kernels_w1().sample_ward(ax, ay, wi.data(), u1.data(), u2.data(), wo.data(), pdf.data(), m);
                return wo;
            };
            auto pdf = [&](float x, float y, float z) {
                const patina::Vec3f a{w1[0], w1[1], w1[2]}, b{x, y, z};
                return double(ward_pdf(a, b, ax, ay));
            };
            EXPECT_GT(sampling_p_value(sample, pdf), 1e-3) << "ward " << ax << " " << ay << " theta " << theta;
            // albedo of the white lobe by importance sampling: at most 1
            std::vector<float> wi, wo(3 * n), p(n);
            for (size_t i = 0; i < n; ++i) wi.insert(wi.end(), w1, w1 + 3);
            lobe_kernels_w1().sample_ward(ax, ay, wi.data(), u1.data(), u2.data(), wo.data(), p.data(), n);
            double albedo = 0;
            for (size_t i = 0; i < n; ++i) {
                if (!(p[i] > 0) || !(wo[3 * i + 2] > 0)) continue;
                const patina::Vec3f a{w1[0], w1[1], w1[2]}, b{wo[3 * i], wo[3 * i + 1], wo[3 * i + 2]};
                albedo += patina::microfacet::ward_eval(a, b, ax, ay, 1.0f) * b.z / p[i];
                // reciprocal, bit for bit: h = wi + wo is symmetric
                ASSERT_EQ(patina::microfacet::ward_eval(a, b, ax, ay, 1.0f),
                          patina::microfacet::ward_eval(b, a, ax, ay, 1.0f));
            }
            EXPECT_LE(albedo / n, 1.0 + 3e-3) << "ward " << ax << " " << ay << " theta " << theta;
        }
    }
    // the wide samplers give the same directions and densities
    const auto wi = hemisphere(4099, 13);
    std::vector<float> s1(wi.size()), p1(wi.size() / 3);
    lobe_kernels_w1().sample_ward(0.2f, 0.05f, wi.data(), u1.data(), u2.data(), s1.data(), p1.data(), p1.size());
    for (int w : {4, 8, 16}) {
        if (!width_supported(w)) continue;
        std::vector<float> sw(wi.size()), pw(wi.size() / 3);
        lobe_kernels_for(w).sample_ward(0.2f, 0.05f, wi.data(), u1.data(), u2.data(), sw.data(), pw.data(), pw.size());
        EXPECT_EQ(sw, s1);
        EXPECT_EQ(pw, p1);
    }
}

// Every lobe kind samples its own pdf (chi-square), at two incidence angles.
TEST(Lobes, EveryKindSamplesItsPdf) {
    using namespace patina::microfacet;
    const size_t n = 1000000;
    const auto u1 = uniforms(n, 14), u2 = uniforms(n, 15);
    for (LobeKind kind : {LobeKind::GGX, LobeKind::Beckmann, LobeKind::BlinnPhong, LobeKind::Ward,
                          LobeKind::AshikhminShirley, LobeKind::Lafortune}) {
        for (float alpha : {0.12f, 0.45f}) {
            const bool exponent =
                kind == LobeKind::BlinnPhong || kind == LobeKind::AshikhminShirley || kind == LobeKind::Lafortune;
            // a Phong lobe about the mirror direction is half as wide in wo as Blinn-Phong's is in h:
            // a quarter of the exponent gives it a like width (and the binning a like resolution)
            const float blinn = 2.0f / (alpha * alpha) - 2.0f;
            const float shape = kind == LobeKind::Lafortune ? 0.25f * blinn : exponent ? blinn : alpha;
            for (double theta : {0.25, 1.1}) {
                const float w1[3] = {float(std::sin(theta)), 0.0f, float(std::cos(theta))};
                auto sample = [&](size_t m) {
                    std::vector<float> wi, wo(3 * m), pdf(m);
                    for (size_t i = 0; i < m; ++i) wi.insert(wi.end(), w1, w1 + 3);
                    lobe_kernels_w1().sample_lobe(kind, shape, wi.data(), u1.data(), u2.data(), wo.data(), pdf.data(), m);
                    return wo;
                };
                auto pdf = [&](float x, float y, float z) {
                    const patina::Vec3f a{w1[0], w1[1], w1[2]}, b{x, y, z};
                    switch (kind) {
                        case LobeKind::GGX: return double(ggx_pdf(a, b, shape));
                        case LobeKind::Beckmann: return double(beckmann_pdf(a, b, shape));
                        case LobeKind::BlinnPhong: return double(blinn_phong_pdf(a, b, shape));
                        case LobeKind::AshikhminShirley: return double(ashikhmin_shirley_pdf(a, b, shape, shape));
                        case LobeKind::Lafortune: return double(lafortune_pdf(a, b, -1.0f, -1.0f, 1.0f, shape));
                        default: return double(ward_pdf(a, b, shape, shape));
                    }
                };
                EXPECT_GT(sampling_p_value(sample, pdf), 1e-3) << "kind " << int(kind) << " alpha " << alpha
                                                                << " theta " << theta;
            }
        }
    }
}

// The anisotropic Ashikhmin-Shirley sampler (its quadrant mapping) against its pdf.
TEST(Lobes, AnisotropicAshikhminShirleySamplesItsPdf) {
    const size_t n = 1000000;
    const auto u1 = uniforms(n, 16), u2 = uniforms(n, 17);
    for (auto [nu, nv] : {std::pair{100.0f, 10.0f}, std::pair{5.0f, 60.0f}}) {
        const float w1[3] = {0.35f, 0.25f, 0.9028842f};
        auto sample = [&](size_t m) {
            std::vector<float> wo(3 * m);
            for (size_t i = 0; i < m; ++i) {
                const patina::Vec3f a{w1[0], w1[1], w1[2]};
                const auto s = patina::microfacet::ashikhmin_shirley_sample(a, u1[i], u2[i], nu, nv);
                wo[3 * i] = s.x;
                wo[3 * i + 1] = s.y;
                wo[3 * i + 2] = s.z;
            }
            return wo;
        };
        auto pdf = [&](float x, float y, float z) {
            return double(patina::microfacet::ashikhmin_shirley_pdf(patina::Vec3f{w1[0], w1[1], w1[2]},
                                                                    patina::Vec3f{x, y, z}, nu, nv));
        };
        EXPECT_GT(sampling_p_value(sample, pdf), 1e-3) << "nu " << nu << " nv " << nv;
    }
}

// Lafortune lobes: reciprocal bit for bit, and each sampler follows its pdf.
TEST(Lobes, LafortuneIsReciprocalAndSamplesItsPdf) {
    using namespace patina::microfacet;
    const size_t n = 1000000;
    const auto u1 = uniforms(n, 18), u2 = uniforms(n, 19);
    struct Lobe {
        float cx, cy, cz, e;
    };
    const auto wi_all = hemisphere(5000, 20), wo_all = hemisphere(5000, 21);
    for (const Lobe& l : {Lobe{-1.0f, -1.0f, 1.0f, 30.0f}, Lobe{-0.8f, -1.2f, 0.9f, 8.0f}, Lobe{0.9f, 0.9f, 0.6f, 15.0f}}) {
        for (size_t i = 0; i < wi_all.size() / 3; ++i) {
            const patina::Vec3f a{wi_all[3 * i], wi_all[3 * i + 1], wi_all[3 * i + 2]};
            const patina::Vec3f b{wo_all[3 * i], wo_all[3 * i + 1], wo_all[3 * i + 2]};
            ASSERT_EQ(lafortune_eval(a, b, l.cx, l.cy, l.cz, l.e, 1.0f), lafortune_eval(b, a, l.cx, l.cy, l.cz, l.e, 1.0f));
        }
        const float w1[3] = {0.45f, 0.2f, 0.8703448f};
        auto sample = [&](size_t m) {
            std::vector<float> wo(3 * m);
            const patina::Vec3f a{w1[0], w1[1], w1[2]};
            for (size_t i = 0; i < m; ++i) {
                const auto s = lafortune_sample(a, u1[i], u2[i], l.cx, l.cy, l.cz, l.e);
                wo[3 * i] = s.x;
                wo[3 * i + 1] = s.y;
                wo[3 * i + 2] = s.z;
            }
            return wo;
        };
        auto pdf = [&](float x, float y, float z) {
            return double(lafortune_pdf(patina::Vec3f{w1[0], w1[1], w1[2]}, patina::Vec3f{x, y, z}, l.cx,
                                        l.cy, l.cz, l.e));
        };
        EXPECT_GT(sampling_p_value(sample, pdf), 1e-3) << "lobe " << l.cx << " " << l.cy << " " << l.cz << " " << l.e;
    }
}

// A clear coat keeps a white Lambert base at or below 1 and stays reciprocal.
TEST(Lobes, ClearCoatKeepsEnergyAndReciprocity) {
    for (float eta : {1.3f, 1.5f, 2.0f}) {
        MixtureParams p = mixture(1, 1, 1, 0.2f, 0, 0, 0);
        p.coat = true;
        p.coat_alpha = 0.05f;
        p.coat_eta = eta;
        const auto wi_r = hemisphere(5000, 22), wo_r = hemisphere(5000, 23);
        EXPECT_EQ(eval(p, wi_r, wo_r), eval(p, wo_r, wi_r));
        for (double theta : {0.0, 0.8, 1.3})
            EXPECT_LE(quadrature_albedo(p, theta), 1.02) << "eta " << eta << " theta " << theta;
    }
}

// Lambert's cosine-weighted sampler follows cos / pi, and its wide paths match width 1.
TEST(Lobes, LambertSamplesItsPdf) {
    const size_t n = 1000000;
    const auto u1 = uniforms(n, 24), u2 = uniforms(n, 25);
    auto sample = [&](size_t m) {
        std::vector<float> wo(3 * m), pdf(m);
        lobe_kernels_w1().sample_lambert(u1.data(), u2.data(), wo.data(), pdf.data(), m);
        return wo;
    };
    auto pdf = [](float, float, float z) { return z > 0 ? double(z) / kPiDouble : 0.0; };
    EXPECT_GT(sampling_p_value(sample, pdf), 1e-3);
    std::vector<float> w1(3 * 1001), p1(1001);
    lobe_kernels_w1().sample_lambert(u1.data(), u2.data(), w1.data(), p1.data(), 1001);
    for (int w : {4, 8, 16}) {
        if (!width_supported(w)) continue;
        std::vector<float> ww(3 * 1001), pw(1001);
        lobe_kernels_for(w).sample_lambert(u1.data(), u2.data(), ww.data(), pw.data(), 1001);
        EXPECT_EQ(ww, w1);
        EXPECT_EQ(pw, p1);
    }
}

// Lafortune lobes with rho (n + 2) / (2 pi), the Phong normalisation, keep energy for a
// mirror-direction lobe (Cx = Cy = -1, Cz = 1).
TEST(Lobes, LafortunePhongLobeKeepsEnergy) {
    const int nmu = 256, nphi = 256;
    for (float e : {5.0f, 50.0f, 500.0f}) {
        for (double theta : {0.0, 0.7, 1.3}) {
            const patina::Vec3f a{float(std::sin(theta)), 0.0f, float(std::cos(theta))};
            double albedo = 0;
            for (int i = 0; i < nmu; ++i)
                for (int j = 0; j < nphi; ++j) {
                    const double mu = (i + 0.5) / nmu, phi = 2 * kPiDouble * (j + 0.5) / nphi, r = std::sqrt(1 - mu * mu);
                    const patina::Vec3f b{float(r * std::cos(phi)), float(r * std::sin(phi)), float(mu)};
                    const float rho = (e + 2.0f) / float(2 * kPiDouble);
                    albedo += patina::microfacet::lafortune_eval(a, b, -1.0f, -1.0f, 1.0f, e, rho) * mu * (1.0 / nmu) *
                              (2 * kPiDouble / nphi);
                }
            EXPECT_LE(albedo, 1.02) << "exponent " << e << " theta " << theta;
        }
    }
}
