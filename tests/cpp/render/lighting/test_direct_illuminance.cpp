// The exact direct illuminance (render/lighting/direct_illuminance.h): a point source gives
// E = I cos / d^2 to float precision, a cylinder sensor I sin(eps) / (pi d^2); a panel casts a
// sharp shadow; a spot follows its smoothstep cone and a goniometric luminaire its table; and
// every width gives the scalar path's bits, lane by lane, for every luminaire and sensor kind
// over a scene with triangles and spheres in the way (with a last packet part full), whatever
// the order the sensors come in.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "core/constants.h"
#include "core/cpu.h"
#include "render/accel/bvh.h"
#include "render/accel/kdtree.h"
#include "render/lighting/direct_illuminance.h"

using namespace patina;

namespace {

constexpr double kDeg = M_PI / 180;

DirectSource point_source(float x, float y, float z, float candela) {
    DirectSource s;
    s.position[0] = x, s.position[1] = y, s.position[2] = z;
    s.scale = candela;
    return s;
}

// A downlight's table over (C, gamma): 1000 cd at the nadir, 700 at 20 degrees, 0 from 40 on.
struct Downlight {
    std::vector<float> c{0.0f, static_cast<float>(2 * M_PI)};
    std::vector<float> gamma{0.0f, static_cast<float>(20 * kDeg), static_cast<float>(40 * kDeg),
                             static_cast<float>(M_PI)};
    std::vector<float> values{1000, 700, 0, 0, 1000, 700, 0, 0};

    static double at(double g) {
        if (g <= 20 * kDeg) return 1000 - 300 * g / (20 * kDeg);
        if (g <= 40 * kDeg) return 700 * (40 * kDeg - g) / (20 * kDeg);
        return 0;
    }
};

// Type C, aimed straight down: gamma from -axis_z, so axis_z is up.
DirectSource downlight(const Downlight& table, float x, float y, float z) {
    DirectSource s = point_source(x, y, z, 1.0f);
    s.kind = SourceKind::Goniometric;
    const float ax[3] = {1, 0, 0}, ay[3] = {0, 0, -1}, az[3] = {0, 1, 0};
    std::memcpy(s.goniometric.axis_x, ax, sizeof ax);
    std::memcpy(s.goniometric.axis_y, ay, sizeof ay);
    std::memcpy(s.goniometric.axis_z, az, sizeof az);
    s.goniometric.candela = Grid2View{table.c.data(), 2, table.gamma.data(), 4, table.values.data()};
    return s;
}

DirectSource spot(float x, float y, float z, float candela) {
    DirectSource s = point_source(x, y, z, candela);
    s.kind = SourceKind::Spot;
    s.spot.cos_inner = static_cast<float>(std::cos(10 * kDeg));
    s.spot.cos_outer = static_cast<float>(std::cos(30 * kDeg));
    return s;
}

// Sensors on a row of the floor (y = 0), facing `normal`.
struct Row {
    std::vector<float> points, normals;
    Row(size_t n, float x0, float x1, const float normal[3]) {
        for (size_t i = 0; i < n; ++i) {
            const float x = x0 + (x1 - x0) * static_cast<float>(i) / static_cast<float>(n - 1);
            points.insert(points.end(), {x, 0.0f, 0.25f});
            normals.insert(normals.end(), normal, normal + 3);
        }
    }
    IlluminanceSensors sensors(SensorKind kind = SensorKind::Planar) const {
        return IlluminanceSensors{kind, points.data(), normals.data(), points.size() / 3};
    }
};

const float kUp[3] = {0, 1, 0};

std::vector<float> lux_of(const std::vector<DirectSource>& sources, const IlluminanceSensors& sensors,
                          const Bvh* occluders, int width, std::vector<float>* per_source = nullptr) {
    const DirectLighting lighting{sources.data(), sources.size(), occluders, 1e-4f};
    std::vector<float> lux(sensors.count);
    if (per_source) per_source->assign(sources.size() * sensors.count, -1.0f);
    direct_illuminance(lighting, sensors, lux.data(), per_source ? per_source->data() : nullptr, width, 1);
    return lux;
}

// The sensor at `p` seen from a light at `light`: unit direction, distance squared, in double.
struct Seen {
    double towards[3], d2;
    Seen(const float* p, const float* light) {
        d2 = 0;
        for (int a = 0; a < 3; ++a) towards[a] = double(light[a]) - p[a], d2 += towards[a] * towards[a];
        for (double& t : towards) t /= std::sqrt(d2);
    }
};

// A panel of two triangles at height y over [x0, x1] x [-1, 1], and two spheres.
Bvh occluders(float y, float x0, float x1) {
    const std::vector<float> v{x0, y, -1, x1, y, -1, x1, y, 1, x0, y, 1};
    const std::vector<int32_t> f{0, 1, 2, 0, 2, 3};
    const KdTree tree = build_kdtree(v.data(), 4, f.data(), 2, KdBuildOptions{});
    Bvh bvh = build_bvh(tree.triangles.data(), tree.triangle_count());
    const float identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const float c1[3] = {-2.5f, 1.0f, 0.3f}, c2[3] = {3.0f, 0.8f, 0.0f};
    bvh.spheres.add(c1, 0.4f, identity);
    bvh.spheres.add(c2, 0.3f, identity);
    return bvh;
}

std::vector<int> widths() {
    std::vector<int> w;
    for (int width : {1, 4, 8, 16})
        if (width_supported(width)) w.push_back(width);
    return w;
}

}  // namespace

TEST(DirectIlluminance, APointSourceGivesICosOverD2ToFloatPrecision) {
    const Row row(101, -6, 6, kUp);
    const std::vector<DirectSource> sources{point_source(0.7f, 2.5f, -0.4f, 800.0f)};
    for (int w : widths()) {
        const std::vector<float> lux = lux_of(sources, row.sensors(), nullptr, w);
        for (size_t i = 0; i < lux.size(); ++i) {
            const Seen s(&row.points[3 * i], sources[0].position);
            const double expected = 800.0 * s.towards[1] / s.d2;
            EXPECT_NEAR(lux[i], expected, 2e-6 * expected) << "width " << w << " sensor " << i;
        }
    }
}

TEST(DirectIlluminance, CylindersTakeSinEpsOverPiAndHalfCylindersTheirFacingHalf) {
    const float facing[3] = {1, 0, 0};
    const Row row(37, -4, 4, facing);
    const std::vector<DirectSource> sources{point_source(0.0f, 3.0f, 0.0f, 500.0f)};
    const std::vector<float> full = lux_of(sources, row.sensors(SensorKind::Cylindrical), nullptr, 1);
    const std::vector<float> half = lux_of(sources, row.sensors(SensorKind::SemiCylindrical), nullptr, 1);
    for (size_t i = 0; i < full.size(); ++i) {
        const Seen s(&row.points[3 * i], sources[0].position);
        const double sin_eps = std::hypot(s.towards[0], s.towards[2]);
        const double cos_alpha = s.towards[0] / sin_eps;  // the light's horizontal direction along +x
        EXPECT_NEAR(full[i], 500.0 * sin_eps / (M_PI * s.d2), 1e-6 * full[i] + 1e-9);
        EXPECT_NEAR(half[i], 500.0 * sin_eps * (1 + cos_alpha) / (M_PI * s.d2), 1e-5 * half[i] + 1e-6);
    }
}

TEST(DirectIlluminance, APanelBetweenLightAndSensorsCastsASharpShadow) {
    const Row row(81, -2, 2, kUp);
    const Bvh occluding = occluders(1.5f, -0.5f, 0.5f);
    const std::vector<DirectSource> sources{point_source(0.0f, 3.0f, 0.25f, 1000.0f)};
    const std::vector<float> lux = lux_of(sources, row.sensors(), &occluding, 1);
    for (size_t i = 0; i < lux.size(); ++i) {
        const float x = row.points[3 * i];
        if (std::fabs(x) < 0.95f) {
            EXPECT_EQ(lux[i], 0.0f) << x;  // the shadow spans |x| < 1
        } else if (std::fabs(x) > 1.05f) {
            EXPECT_GT(lux[i], 0.0f) << x;
        }
    }
}

TEST(DirectIlluminance, ASpotFollowsItsSmoothstepConeAndADownlightItsTable) {
    const Downlight table;
    const Row row(64, 0, 3, kUp);
    const std::vector<DirectSource> sources{spot(0.0f, 2.0f, 0.25f, 500.0f), downlight(table, 0.0f, 2.0f, 0.25f)};
    std::vector<float> per_source;
    lux_of(sources, row.sensors(), nullptr, 1, &per_source);
    const size_t n = row.points.size() / 3;
    for (size_t i = 0; i < n; ++i) {
        const Seen s(&row.points[3 * i], sources[0].position);
        const double cos_t = s.towards[1], gamma = std::acos(cos_t);
        const double t = std::clamp((cos_t - std::cos(30 * kDeg)) / (std::cos(10 * kDeg) - std::cos(30 * kDeg)), 0.0,
                                    1.0);
        const double cone = 500.0 * t * t * (3 - 2 * t) * cos_t / s.d2;
        const double table_lux = Downlight::at(gamma) * cos_t / s.d2;
        EXPECT_NEAR(per_source[i], cone, 1e-5 * cone + 1e-6) << i;
        // the fast acos is within 5e-7 rad: 300 cd per 20 degrees moves by < 1e-3 cd
        EXPECT_NEAR(per_source[n + i], table_lux, 2e-5 * table_lux + 1e-3 / s.d2) << i;
    }
}

TEST(DirectIlluminance, EveryWidthGivesTheScalarPathsBitsLaneByLane) {
    const Downlight table;
    std::vector<DirectSource> sources{point_source(-1.0f, 2.5f, 0.5f, 700.0f), spot(1.5f, 3.0f, -0.5f, 900.0f),
                                      downlight(table, 0.5f, 2.8f, 0.0f)};
    DirectSource tilted = downlight(table, -2.0f, 2.2f, 1.0f);
    tilted.goniometric.type_b = true;  // the same table read as type B, aimed along its frame's +z (up)
    sources.push_back(tilted);
    const Bvh occluding = occluders(1.2f, -1.0f, 0.2f);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> along(-5.0f, 5.0f), unit(-1.0f, 1.0f);
    std::vector<float> points, normals;
    for (int i = 0; i < 16 * 40 + 11; ++i) {  // a last packet part full at every width
        points.insert(points.end(), {along(rng), 0.3f * unit(rng), along(rng)});
        const float nx = unit(rng), ny = unit(rng), nz = unit(rng), len = std::sqrt(nx * nx + ny * ny + nz * nz);
        normals.insert(normals.end(), {nx / len, ny / len, nz / len});
    }
    for (SensorKind kind : {SensorKind::Planar, SensorKind::Cylindrical, SensorKind::SemiCylindrical}) {
        const IlluminanceSensors sensors{kind, points.data(), normals.data(), points.size() / 3};
        std::vector<float> scalar_terms, open_terms, terms;
        const std::vector<float> scalar = lux_of(sources, sensors, &occluding, 1, &scalar_terms);
        lux_of(sources, sensors, nullptr, 1, &open_terms);
        size_t shadowed = 0;
        for (size_t j = 0; j < scalar_terms.size(); ++j) shadowed += open_terms[j] > 0 && scalar_terms[j] == 0;
        EXPECT_GT(shadowed, 0u);  // the occluders hide some luminaire from some sensor
        for (int w : widths()) {
            const std::vector<float> wide = lux_of(sources, sensors, &occluding, w, &terms);
            for (size_t i = 0; i < scalar.size(); ++i)
                ASSERT_EQ(std::memcmp(&wide[i], &scalar[i], sizeof(float)), 0)
                    << "width " << w << " sensor " << i << ": " << wide[i] << " vs " << scalar[i];
            for (size_t j = 0; j < terms.size(); ++j)
                ASSERT_EQ(std::memcmp(&terms[j], &scalar_terms[j], sizeof(float)), 0) << "width " << w << " term " << j;
        }
    }
}

TEST(DirectIlluminance, TheSensorsOrderChangesNothingButTheOrder) {
    const Bvh occluding = occluders(1.2f, -1.0f, 0.2f);
    const std::vector<DirectSource> sources{point_source(-1.0f, 2.5f, 0.5f, 700.0f), spot(1.5f, 3.0f, -0.5f, 900.0f)};
    const Row row(203, -5, 5, kUp);
    std::vector<size_t> shuffled(row.points.size() / 3);
    for (size_t i = 0; i < shuffled.size(); ++i) shuffled[i] = i;
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(3));
    std::vector<float> points, normals;
    for (size_t i : shuffled) {
        points.insert(points.end(), &row.points[3 * i], &row.points[3 * i] + 3);
        normals.insert(normals.end(), &row.normals[3 * i], &row.normals[3 * i] + 3);
    }
    const std::vector<float> lux = lux_of(sources, row.sensors(), &occluding, 0);
    const IlluminanceSensors reordered{SensorKind::Planar, points.data(), normals.data(), shuffled.size()};
    const std::vector<float> lux_shuffled = lux_of(sources, reordered, &occluding, 0);
    for (size_t j = 0; j < shuffled.size(); ++j)
        ASSERT_EQ(std::memcmp(&lux_shuffled[j], &lux[shuffled[j]], sizeof(float)), 0) << j;
}
