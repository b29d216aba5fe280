// The renderer's RGL material (render/materials/rgl_material.h) N lanes at a time, lane by lane
// against width 1: its value, pdf and samples bit-identical, by the file's warps and by the
// cosine, isotropic and anisotropic (reduced) files, pairs above and below the horizon.
// Included after tests/cpp/core/simd/simd_lane_tests.h (its fixture) by test_simd_w{4,8,16}.cpp.
#pragma once

#include <random>

#include "render/materials/rgl_material.h"
#include "tests/cpp/brdf/rgl/rgl_test_material.h"

namespace {

// N random unit directions, a fifth of them below the horizon.
Vec3<F> random_directions(std::mt19937& rng, Vec3<float> (&rows)[N]) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    float x[N], y[N], z[N];
    for (int j = 0; j < N; ++j) {
        const float cos_t = 1.2f * u(rng) - 0.2f, sin_t = std::sqrt(1.0f - cos_t * cos_t);
        const float phi = 6.2831853f * u(rng);
        rows[j] = Vec3<float>{sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
        x[j] = rows[j].x, y[j] = rows[j].y, z[j] = rows[j].z;
    }
    return Vec3<F>{load_n<N>(x), load_n<N>(y), load_n<N>(z)};
}

F random_lanes(std::mt19937& rng, float (&lanes)[N]) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (float& x : lanes) x = u(rng);
    return load_n<N>(lanes);
}

void expect_same_rows(const Vec3<F>& wide, const Vec3<float>& narrow, int j, const char* what, int trial) {
    ASSERT_TRUE(same_float(lane(wide.x, j), narrow.x) && same_float(lane(wide.y, j), narrow.y) &&
                same_float(lane(wide.z, j), narrow.z))
        << what << ", lane " << j << ", trial " << trial;
}

void expect_rgl_lanes_match_scalar(const patina::RglMaterial& m) {
    std::mt19937 rng(17);
    int nonzero = 0;
    for (int trial = 0; trial < 200; ++trial) {
        Vec3<float> l_rows[N], v_rows[N];
        float u1_lanes[N], u2_lanes[N];
        const Vec3<F> l = random_directions(rng, l_rows), v = random_directions(rng, v_rows);
        const F u1 = random_lanes(rng, u1_lanes), u2 = random_lanes(rng, u2_lanes);
        const Vec3<F> f = materials::eval(m, l, v, F(1.0f));
        const F pdf = materials::pdf(m, l, v, F(1.0f));
        const Vec3<F> sampled = materials::sample(m, v, F(0.0f), u1, u2, F(1.0f));
        for (int j = 0; j < N; ++j) {
            expect_same_rows(f, materials::eval(m, l_rows[j], v_rows[j], 1.0f), j, "value", trial);
            ASSERT_TRUE(same_float(lane(pdf, j), materials::pdf(m, l_rows[j], v_rows[j], 1.0f)))
                << "pdf, lane " << j << ", trial " << trial;
            expect_same_rows(sampled, materials::sample(m, v_rows[j], 0.0f, u1_lanes[j], u2_lanes[j], 1.0f), j,
                             "sample", trial);
            nonzero += lane(f.x, j) > 0.0f && lane(pdf, j) > 0.0f;
        }
    }
    EXPECT_GT(nonzero, 200 * N / 5);  // real values compared, not zeros
}

}  // namespace

LANE_TEST(RglMaterialMatchesScalar) {
    for (bool isotropic : {true, false}) {
        const patina::test::RglTestMaterial file(isotropic, isotropic ? 1 : 2);
        patina::RglMaterial m;
        m.rgl = &file.view;
        m.tint[1] = 0.5f;
        for (bool cosine : {false, true}) {
            m.cosine_sampling = cosine;
            expect_rgl_lanes_match_scalar(m);
        }
    }
}
