// cache-guided's guides (render/cache/guided_distribution.h, guided_bounces_impl.h): the cdf
// over texels is a distribution with every texel above its floor and the cells averaged;
// a cache point's guide is a density over the sphere (integrates to one) whose samples it
// gives their own density; the pool finds the point of least reuse error within the bound
// (its normal close enough).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/constants.h"
#define PATINA_KERNEL_WIDTH 1
#include "render/cache/guided_bounces_impl.h"
#include "render/samplers/rng.h"

using namespace patina;
using namespace patina::cache;

namespace {

CachePoint point_at(Vec3f p, Vec3f n, float radius, int R) {
    CachePoint a;
    a.p = p;
    a.n = a.ng = normalize(n);
    orthonormal_frame(a.n, a.t, a.b);
    a.resolution = R;
    a.reuse_radius = radius;
    a.radiance.assign(3 * static_cast<size_t>(R) * R, 0.0f);
    return a;
}

float probability(const std::vector<float>& cdf, size_t t) { return cdf[t] - (t > 0 ? cdf[t - 1] : 0.0f); }

}  // namespace

TEST(GuidedDistribution, IsADistributionWithAFloorUnderEveryTexelAndTheCellsAveraged) {
    const int R = 12;
    const size_t T = R * R;
    std::vector<float> radiance(3 * T, 0.0f), cosz(T, 1.0f), cell(3 * T), cdf(T);
    // one bright texel in an otherwise black hemisphere (a single lucky path sample)
    const size_t bright = 5 * R + 7;
    for (int k = 0; k < 3; ++k) radiance[3 * bright + k] = 9.0f;
    ASSERT_TRUE(guide_cdf(radiance.data(), cosz.data(), R, cell.data(), cdf.data()));
    EXPECT_FLOAT_EQ(cdf[T - 1], 1.0f);
    double sum = 0;
    for (size_t t = 0; t < T; ++t) {
        const float p = probability(cdf, t);
        EXPECT_GT(p, 0.0f) << t;  // the floor: no texel the guide never draws
        sum += p;
    }
    EXPECT_NEAR(sum, 1.0, 1e-5);
    // the bright texel's light is shared by the texels of its cell, equally
    const int ci = (7 / kGuideCell) * kGuideCell, cj = (5 / kGuideCell) * kGuideCell;
    const float shared = probability(cdf, static_cast<size_t>(cj * R + ci));
    for (int j = cj; j < cj + kGuideCell; ++j)
        for (int i = ci; i < ci + kGuideCell; ++i) EXPECT_NEAR(probability(cdf, j * R + i), shared, 1e-6f);
    // ... and the cell takes all of the light but the floor
    EXPECT_NEAR(shared * kGuideCell * kGuideCell, (1.0 + kGuideFloor / T * kGuideCell * kGuideCell) / (1.0 + kGuideFloor), 1e-4);
    // no light at all: no guide
    std::vector<float> black(3 * T, 0.0f);
    EXPECT_FALSE(guide_cdf(black.data(), cosz.data(), R, cell.data(), cdf.data()));
}

TEST(GuidedBounces, AGuideIsADensityOverTheSphereThatItsSamplesFollow) {
    const int R = 16;
    CachePoint a = point_at({0, 0, 0}, {0.3f, 0.2f, 1.0f}, 1.0f, R);
    for (size_t t = 0; t < a.radiance.size() / 3; ++t)
        for (int k = 0; k < 3; ++k) a.radiance[3 * t + k] = static_cast<float>((t * 7919) % 13);
    std::vector<const CachePoint*> pool{&a};
    GuidePool g;
    g.prepare(pool, R);
    TexelDirections dirs;
    dirs.prepare(R);
    const float* cdf = g.guide(0, dirs);
    ASSERT_NE(cdf, nullptr);
    // integral over the sphere of the density, by uniform sphere samples: one
    const int n = 200000;
    double integral = 0;
    for (int i = 0; i < n; ++i) {
        const float z = 1.0f - 2.0f * uniform(7u, 2u * i), phi = kTwoPi * uniform(7u, 2u * i + 1);
        const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
        integral += pool_guide_pdf(a, cdf, R, {r * std::cos(phi), r * std::sin(phi), z});
    }
    EXPECT_NEAR(integral * 4.0 * kPi / n, 1.0, 0.01);
    // the samples: in the point's hemisphere, unit, of positive density; and E[1 / pdf]
    // over them is the measure of where the density is positive (the hemisphere, 2 pi)
    double inverse = 0;
    for (int i = 0; i < n; ++i) {
        const Vec3f d = pool_guide_sample(a, cdf, R, uniform(9u, 3u * i), uniform(9u, 3u * i + 1), uniform(9u, 3u * i + 2));
        ASSERT_NEAR(dot(d, d), 1.0f, 1e-4f);
        ASSERT_GT(dot(d, a.n), 0.0f);
        const float p = pool_guide_pdf(a, cdf, R, d);
        ASSERT_GT(p, 0.0f);
        inverse += 1.0 / p;
    }
    EXPECT_NEAR(inverse / n, 2.0 * kPi, 0.02 * 2.0 * kPi);
}

TEST(GuidedBounces, ThePoolFindsThePointOfLeastErrorWithinTheBound) {
    const int R = 8;
    std::vector<CachePoint> points = {
        point_at({0, 0, 0}, {0, 0, 1}, 1.0f, R),
        point_at({0.6f, 0, 0}, {0, 0, 1}, 1.0f, R),
        point_at({0.3f, 0, 0}, {0, 0, -1}, 1.0f, R),  // the other side
        point_at({40, 0, 0}, {0.25f, 0, 1}, INFINITY, R),  // saw nothing: reaches everywhere, error 0.17
    };
    std::vector<const CachePoint*> pool;
    for (const CachePoint& a : points) pool.push_back(&a);
    GuidePool g;
    g.prepare(pool, R);
    const Vec3f up{0, 0, 1};
    EXPECT_EQ(g.find({0.1f, 0, 0}, up), 0);
    EXPECT_EQ(g.find({0.5f, 0.1f, 0}, up), 1);
    EXPECT_EQ(g.find({0.3f, 0, 0}, {0, 0, -1}), 2);
    // beyond every finite reach: the unbounded point, whose error is its normals' term alone
    EXPECT_EQ(g.find({10, 0, 0}, up), 3);
    // each answer is the brute-force least error within the bound
    for (int i = 0; i < 200; ++i) {
        const Vec3f p{4 * uniform(3u, 3u * i) - 2, 4 * uniform(3u, 3u * i + 1) - 2, 0.5f * uniform(3u, 3u * i + 2)};
        const Vec3f n = normalize(Vec3f{uniform(5u, 2u * i) - 0.5f, 0, 1});
        int32_t best = -1;
        float best_error = kGuideBound;
        for (size_t a = 0; a < points.size(); ++a) {
            if (!(dot(points[a].n, n) >= kGuideCos)) continue;
            const float e = reuse_error(points[a], p, n);
            if (e <= best_error && (best < 0 || e < best_error)) best = static_cast<int32_t>(a), best_error = e;
        }
        EXPECT_EQ(g.find(p, n), best) << i;
    }
}
