// Light selection (render/lights/selection_impl.h) through the render kernels' light_selection:
// a delta light's probability follows its intensity towards the point (a luminaire's candela
// table, a spot's cone) over d^2, 0 exactly where it sends nothing; the probabilities sum to
// 1; the pick's probability (N points at a time) is the MIS weights' (one point, width 1)
// and the same bits at every width; no NaN, a point at a light included.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/constants.h"
#include "core/cpu.h"
#include "render/integrators/integrator.h"
#include "render/scene.h"

using namespace patina;

namespace {

constexpr double kDeg = M_PI / 180;

// A downlight's candela table over (C, gamma): rotationally symmetric, 1000 cd at the nadir
// falling linearly to 700 at 20 degrees and to 0 at 40 (its cut-off), 0 beyond.
struct Downlight {
    std::vector<float> c{0.0f, static_cast<float>(2 * M_PI)};
    std::vector<float> gamma{0.0f, static_cast<float>(20 * kDeg), static_cast<float>(40 * kDeg),
                             static_cast<float>(M_PI)};
    std::vector<float> values{1000, 700, 0, 0, 1000, 700, 0, 0};  // values[ic * 4 + igamma]

    Grid2View view() const { return Grid2View{c.data(), 2, gamma.data(), 4, values.data()}; }

    // the table at gamma (radians), in double
    static double at(double g) {
        if (g <= 20 * kDeg) return 1000 - 300 * g / (20 * kDeg);
        if (g <= 40 * kDeg) return 700 * (40 * kDeg - g) / (20 * kDeg);
        return 0;
    }
};

// A luminaire at `at` aimed straight down (type C: gamma from -axis_z, so axis_z is up).
GoniometricLight downlight(const Downlight& table, Vec3f at, float per_cd) {
    GoniometricLight l;
    const float pos[3] = {at.x, at.y, at.z}, x[3] = {1, 0, 0}, y[3] = {0, 0, -1}, z[3] = {0, 1, 0};
    for (int k = 0; k < 3; ++k)
        l.position[k] = pos[k], l.axis_x[k] = x[k], l.axis_y[k] = y[k], l.axis_z[k] = z[k],
        l.rgb_per_candela[k] = per_cd;
    l.candela = table.view();
    return l;
}

// A scene of lights only (the selection reads no geometry): scene_radius sets its size floor.
RenderScene light_scene(std::vector<Light> lights, float environment = 0) {
    RenderScene s;
    s.scene_radius = 5;
    s.lights = std::move(lights);
    if (environment > 0) {
        s.env.present = true;
        s.env.constant[0] = s.env.constant[1] = s.env.constant[2] = environment;
    }
    prepare_light_selection(s);
    return s;
}

// Per point, each light's probability as the pick computes it and as an MIS weight does.
struct Probabilities {
    std::vector<float> pick, mis;
};

Probabilities selection(const RenderScene& s, const std::vector<float>& points, int width) {
    const size_t n = points.size() / 3, count = s.selection.size();
    Probabilities p{std::vector<float>(n * count), std::vector<float>(n * count)};
    render_kernels_for(width).light_selection(s, points.data(), n, p.pick.data(), p.mis.data());
    return p;
}

}  // namespace

TEST(LightSelection, ALuminaireSendingAPointNothingIsNeverPicked) {
    const Downlight table;
    const RenderScene s = light_scene({Light{downlight(table, {-1, 3, 0}, 1)}, Light{downlight(table, {1, 3, 0}, 1)}});
    // (-2, 0, 0): 18 degrees off the first one's nadir, 45 off the second's (beyond its 40)
    const Probabilities p = selection(s, {-2, 0, 0}, 0);
    EXPECT_EQ(p.pick[1], 0.0f);
    EXPECT_EQ(p.pick[0], 1.0f);
    // between them, both lit alike (mirror images): half each
    const Probabilities mid = selection(s, {0, 0, 0.5f}, 0);
    EXPECT_NEAR(mid.pick[0], 0.5f, 1e-6f);
    EXPECT_NEAR(mid.pick[1], 0.5f, 1e-6f);
}

TEST(LightSelection, ALightAloneIsEveryPointsPick) {
    // its weight not computed (a scene of one light pays nothing for the selection): even where
    // the luminaire sends nothing, its sample (0) is taken with probability 1
    const Downlight table;
    const RenderScene s = light_scene({Light{downlight(table, {-1, 3, 0}, 1)}});
    const Probabilities p = selection(s, {-1, 0, 0, 3, 0, 0, -1, 3, 0}, 0);
    for (int q = 0; q < 3; ++q) {
        EXPECT_EQ(p.pick[q], 1.0f) << "point " << q;
        EXPECT_EQ(p.mis[q], 1.0f) << "point " << q;
    }
}

TEST(LightSelection, ProbabilitiesFollowTheCandelaTableAndTheConeOverDistanceSquared) {
    const Downlight table;
    SpotLight spot;
    const float sp[3] = {0, 2, 2}, sd[3] = {0, -1, 0};
    for (int k = 0; k < 3; ++k) spot.position[k] = sp[k], spot.direction[k] = sd[k], spot.intensity[k] = 3;
    spot.cos_inner = static_cast<float>(std::cos(15 * kDeg));
    spot.cos_outer = static_cast<float>(std::cos(30 * kDeg));
    PointLight point;
    const float pp[3] = {2, 2.5f, -1};
    for (int k = 0; k < 3; ++k) point.position[k] = pp[k], point.intensity[k] = 0.5f;
    const Vec3f a{-1, 3, 0}, b{1, 3, 0};
    const RenderScene s =
        light_scene({Light{downlight(table, a, 0.02f)}, Light{downlight(table, b, 0.01f)}, Light{spot}, Light{point}},
                    0.05f);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-2.5f, 2.5f);
    std::vector<float> points;
    for (int i = 0; i < 200; ++i) points.insert(points.end(), {u(rng), 0.25f * (u(rng) + 2.5f), u(rng)});
    const Probabilities p = selection(s, points, 0);
    int outside_a = 0, outside_spot = 0;
    for (size_t q = 0; q < points.size() / 3; ++q) {
        const double x = points[3 * q], y = points[3 * q + 1], z = points[3 * q + 2];
        auto d2 = [&](double ax, double ay, double az) {
            return (ax - x) * (ax - x) + (ay - y) * (ay - y) + (az - z) * (az - z);
        };
        auto luminaire = [&](Vec3f at, double per_cd) {
            const double d = std::sqrt(d2(at.x, at.y, at.z));
            return per_cd * Downlight::at(std::acos((at.y - y) / d)) / (d * d);
        };
        const double cone = std::clamp(((sp[1] - y) / std::sqrt(d2(sp[0], sp[1], sp[2])) - spot.cos_outer) /
                                           (spot.cos_inner - spot.cos_outer), 0.0, 1.0);
        const double w[5] = {luminaire(a, 0.02), luminaire(b, 0.01),
                             3 * cone * cone * (3 - 2 * cone) / d2(sp[0], sp[1], sp[2]),
                             0.5 / d2(pp[0], pp[1], pp[2]), M_PI * 0.05};  // the environment: irradiance pi L
        // each weight's largest value at this distance: the profile is read at the angle of a
        // float direction through fast_acos (3e-7 rad), a few 1e-7 of its peak where steepest
        const double peak[5] = {20 / d2(a.x, a.y, a.z), 10 / d2(b.x, b.y, b.z), 3 / d2(sp[0], sp[1], sp[2]), w[3],
                                w[4]};
        const double sum = w[0] + w[1] + w[2] + w[3] + w[4];
        double total = 0;
        for (int k = 0; k < 5; ++k) {
            const float got = p.pick[q * 5 + k];
            total += got;
            if (w[k] == 0) {
                EXPECT_EQ(got, 0.0f) << "point " << q << " light " << k;
            }
            EXPECT_NEAR(got, w[k] / sum, 1e-5 * peak[k] / sum) << "point " << q << " light " << k;
        }
        EXPECT_NEAR(total, 1.0, 1e-6) << "point " << q;
        outside_a += w[0] == 0;
        outside_spot += w[2] == 0;
    }
    EXPECT_GT(outside_a, 20);  // the cases above are there: points outside a cone...
    EXPECT_GT(outside_spot, 20);
    EXPECT_LT(outside_spot, 190);  // ...and inside it
}

TEST(LightSelection, ThePicksProbabilityIsTheMisWeightsAndTheSameBitsAtEveryWidth) {
    const Downlight table;
    GoniometricLight type_b = downlight(table, {0.5f, 2.5f, -1}, 0.02f);
    type_b.type_b = true;  // a floodlight (its beam along axis_z) aimed down and sideways
    const float ax[3] = {0, 0, 1}, ay[3] = {-0.8f, -0.6f, 0}, az[3] = {0.6f, -0.8f, 0};
    for (int k = 0; k < 3; ++k) type_b.axis_x[k] = ax[k], type_b.axis_y[k] = ay[k], type_b.axis_z[k] = az[k];
    SpotLight spot;
    spot.position[1] = 2;
    spot.cos_inner = 0.95f, spot.cos_outer = 0.8f;
    QuadLight quad;  // an area light: weighed as before, by flux
    quad.center[1] = 2.9f;
    quad.area = 0.16f;
    const Light a{downlight(table, {-1, 3, 0}, 0.02f)}, b{downlight(table, {1, 3, 0}, 0.01f)};
    const RenderScene s = light_scene({a, Light{type_b}, Light{spot}, Light{quad}, b}, 0.05f);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f);
    // random points, then the lights' own positions (d = 0) and points on a cone's axis
    std::vector<float> points;
    for (int i = 0; i < 301; ++i) points.insert(points.end(), {u(rng), 0.5f * (u(rng) + 3.0f), u(rng)});
    points.insert(points.end(), {-1, 3, 0, 0.5f, 2.5f, -1, 0, 2, 0, 0, 2.9f, 0, 0, 0, 0, -1, 0, 0});
    const size_t n = points.size() / 3, count = s.selection.size();
    const Probabilities ref = selection(s, points, 1);
    for (size_t q = 0; q < n; ++q) {
        double total = 0;
        for (size_t k = 0; k < count; ++k) {
            const float v = ref.pick[q * count + k];
            ASSERT_TRUE(std::isfinite(v) && v >= 0) << "point " << q << " light " << k;
            total += v;
        }
        EXPECT_NEAR(total, 1.0, 1e-6) << "point " << q;
    }
    EXPECT_EQ(ref.pick[(n - 6) * count + 0], 0.0f);  // at a light: never picked, the others still are
    EXPECT_EQ(ref.pick[(n - 4) * count + 2], 0.0f);
    for (int width : {1, 4, 8, 16}) {
        if (!width_supported(width)) continue;
        const Probabilities got = selection(s, points, width);
        for (size_t i = 0; i < n * count; ++i) {
            const size_t q = i / count, k = i % count;
            ASSERT_EQ(got.pick[i], ref.pick[i]) << "width " << width << " point " << q << " light " << k;
            ASSERT_EQ(got.mis[i], got.pick[i]) << "width " << width << " point " << q << " light " << k;
        }
    }
}
