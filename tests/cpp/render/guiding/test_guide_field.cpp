// cache-guided's trained guide (render/guiding/): a directional quadtree is a density on the
// square (integrates to one) whose samples have that density (a chi-square test), fine where
// the samples' energy is and never finer than its samples resolve; the field's distribution
// over the sphere integrates to one and its samples have its density; a field built from
// records of light from one direction sends its samples there; the same records give the
// same field, bit for bit.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/constants.h"
#include "render/guiding/directional_tree.h"
#include "render/guiding/guide_field.h"
#include "render/guiding/sphere_square.h"
#include "render/samplers/rng.h"

using namespace patina;
using namespace patina::guiding;

namespace {

float test_uniform(uint32_t stream, uint32_t i) { return static_cast<float>(hash_u32(hash_u32(stream) ^ i) >> 8) * 0x1p-24f; }

// n samples: a share `bright` of them in a small square around (0.7, 0.3) of weight 10, the rest
// uniform of weight 1
void skewed_samples(size_t n, float bright, std::vector<float>& uv, std::vector<float>& w) {
    uv.resize(2 * n);
    w.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const float a = test_uniform(1, static_cast<uint32_t>(i)), b = test_uniform(2, static_cast<uint32_t>(i));
        const bool in = test_uniform(3, static_cast<uint32_t>(i)) < bright;
        uv[2 * i] = in ? 0.68f + 0.04f * a : a;
        uv[2 * i + 1] = in ? 0.28f + 0.04f * b : b;
        w[i] = in ? 10.0f : 1.0f;
    }
}

// Chi-square of `draws` samples of the tree against its density, over a G x G grid of the square.
double chi_square(const DirectionalTree& tree, int G, int draws, int& cells_used) {
    std::vector<double> expected(G * G, 0.0), seen(G * G, 0.0);
    const int S = 8;  // sub-samples a cell for the expected counts (cells are at least 1/64 wide)
    for (int j = 0; j < G * S; ++j)
        for (int i = 0; i < G * S; ++i) {
            const float u = (i + 0.5f) / (G * S), v = (j + 0.5f) / (G * S);
            expected[(j / S) * G + i / S] += tree.density(u, v) / (G * S * G * S) * draws;
        }
    for (int k = 0; k < draws; ++k) {
        float u, v;
        tree.sample(test_uniform(7, k), test_uniform(8, k), u, v);
        seen[std::min(G - 1, static_cast<int>(v * G)) * G + std::min(G - 1, static_cast<int>(u * G))] += 1;
    }
    double chi = 0;
    cells_used = 0;
    for (int c = 0; c < G * G; ++c)
        if (expected[c] > 5) chi += (seen[c] - expected[c]) * (seen[c] - expected[c]) / expected[c], ++cells_used;
    return chi;
}

}  // namespace

TEST(DirectionalTree, IsADensityWhoseSamplesHaveIt) {
    std::vector<float> uv, w;
    skewed_samples(20000, 0.2f, uv, w);
    DirectionalTree tree;
    tree.build(uv.data(), w.data(), 20000);
    ASSERT_FALSE(tree.empty());
    EXPECT_GT(tree.nodes(), 4u);  // subdivided where the energy is
    // integrates to one over the square (midpoint rule on a grid finer than its leaves)
    const int M = 1024;
    double sum = 0;
    for (int j = 0; j < M; ++j)
        for (int i = 0; i < M; ++i) sum += tree.density((i + 0.5f) / M, (j + 0.5f) / M);
    EXPECT_NEAR(sum / (M * M), 1.0, 1e-3);
    // denser in the bright square than anywhere else, and above the floor everywhere
    EXPECT_GT(tree.density(0.7f, 0.3f), 10 * tree.density(0.2f, 0.8f));
    EXPECT_GT(tree.density(0.2f, 0.8f), 0.05f);
    int cells = 0;
    const double chi = chi_square(tree, 32, 200000, cells);
    // chi-square with cells - 1 degrees of freedom: mean cells - 1, sd sqrt(2 (cells - 1))
    EXPECT_LT(chi, cells - 1 + 5 * std::sqrt(2.0 * (cells - 1))) << cells;
}

TEST(DirectionalTree, ASingleBrightSampleDoesNotGrowASpike) {
    std::vector<float> uv, w;
    skewed_samples(1000, 0.0f, uv, w);
    w[17] = 1e6f;  // a firefly
    DirectionalTree tree;
    DirectionalTreeParams p;
    tree.build(uv.data(), w.data(), 1000, p);
    // subdivided only while a quadrant holds min_split_samples samples: with 1000 uniform
    // samples no leaf is smaller than 1/16 of the square a side or so
    const float u = uv[34], v = uv[35];
    EXPECT_LT(tree.density(u, v), 16 * 16 * 1.0f);
}

TEST(DirectionalTree, NothingToSampleWithoutEnergy) {
    std::vector<float> uv(20, 0.5f), w(10, 0.0f);
    DirectionalTree tree;
    tree.build(uv.data(), w.data(), 10);
    EXPECT_TRUE(tree.empty());
    EXPECT_EQ(tree.density(0.5f, 0.5f), 0.0f);
}

// The lookup by direction (its top table, then sign tests against the cells' azimuth
// boundaries) finds the leaf the azimuth finds: the densities agree but within rounding of a
// boundary. A tree coarser than the top table, one as deep as the defaults allow (cells of
// 1/1024 a side where the light is), and one deeper than the boundaries' table (its last
// levels by the azimuth).
TEST(DirectionalTree, TheLookupByDirectionIsTheLookupByAzimuth) {
    for (const int depth : {2, 10, AzimuthBoundaries::kLevels + 3}) {
        std::vector<float> uv, w;
        skewed_samples(200000, 0.5f, uv, w);
        for (size_t i = 0; i < w.size(); i += 7) uv[2 * i] = 0.5f + 1e-4f * test_uniform(4, static_cast<uint32_t>(i));
        DirectionalTree tree;
        DirectionalTreeParams p;
        p.max_depth = depth;
        p.split_fraction = 0.001f;
        tree.build(uv.data(), w.data(), w.size(), p);
        int differ = 0;
        const int n = 200000;
        for (int k = 0; k < n; ++k) {
            float d[3], u, v;
            // half the directions near the tree's finest cells, around u = 0.5 (the root's
            // boundary, its half-turn test) and the bright square
            const float su = k % 2 ? test_uniform(5, k) : (k % 4 ? 0.5f + 2e-4f * (test_uniform(5, k) - 0.5f)
                                                                 : 0.68f + 0.04f * test_uniform(5, k));
            square_to_direction(su, test_uniform(6, k), d);
            direction_to_square(d, u, v);
            if (tree.density_at_direction(d) != tree.density(u, v)) ++differ;
        }
        EXPECT_LT(differ, n / 5000) << depth;
    }
    EXPECT_EQ(DirectionalTree().density_at_direction(std::array<float, 3>{0, 0, 1}.data()), 0.0f);
}

TEST(SphereSquare, TheMapAndItsInverseAgree) {
    for (int k = 0; k < 1000; ++k) {
        float d[3], u, v, e[3];
        square_to_direction(test_uniform(11, k), test_uniform(12, k), d);
        EXPECT_NEAR(d[0] * d[0] + d[1] * d[1] + d[2] * d[2], 1.0f, 1e-5f);
        direction_to_square(d, u, v);
        square_to_direction(u, v, e);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(d[c], e[c], 1e-4f);
    }
}

namespace {

// Records at points of the unit cube, light from around direction `from` (a cone of 0.2 rad)
// and a little from everywhere.
std::vector<GuideRecord> cone_records(size_t n, const float* from) {
    std::vector<GuideRecord> r(n);
    for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) r[i].p[c] = test_uniform(20 + c, static_cast<uint32_t>(i));
        r[i].n[0] = r[i].n[1] = 0.0f;
        r[i].n[2] = 1.0f;
        float d[3];
        square_to_direction(test_uniform(30, static_cast<uint32_t>(i)), test_uniform(31, static_cast<uint32_t>(i)), d);
        const bool lit = test_uniform(32, static_cast<uint32_t>(i)) < 0.3f;
        if (lit) {
            for (int c = 0; c < 3; ++c) d[c] = from[c] + 0.2f * d[c];
            const float len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            for (int c = 0; c < 3; ++c) d[c] /= len;
        }
        for (int c = 0; c < 3; ++c) r[i].d[c] = d[c];
        r[i].value = lit ? 20.0f : 0.5f;
    }
    return r;
}

}  // namespace

const float up[3] = {0.0f, 0.0f, 1.0f};

TEST(GuideField, ItsDistributionsIntegrateToOneAndSendSamplesWhereTheLightIs) {
    const float from[3] = {0.0f, 0.6f, 0.8f};
    GuideField field;
    field.build(cone_records(20000, from));
    ASSERT_FALSE(field.empty());
    EXPECT_GT(field.leaves(), 4u);  // split over space: 20000 records, at most 2000 a leaf
    const float p[3] = {0.3f, 0.6f, 0.4f};
    const int32_t k = field.distribution_at(p, up);
    ASSERT_GE(k, 0);
    // over the sphere: a grid of the square (equal areas are equal solid angles)
    const int M = 512;
    double sum = 0;
    for (int j = 0; j < M; ++j)
        for (int i = 0; i < M; ++i) {
            float d[3];
            square_to_direction((i + 0.5f) / M, (j + 0.5f) / M, d);
            sum += field.pdf(k, d) * (4 * kPi) / (M * M);
        }
    EXPECT_NEAR(sum, 1.0, 2e-3);
    // the samples' density is the pdf: their mean of 1 / pdf is the sphere's area, and most
    // of them come from around the light's direction
    double inv = 0;
    int near = 0;
    const int draws = 100000;
    for (int s = 0; s < draws; ++s) {
        float d[3];
        field.sample(k, test_uniform(40, s), test_uniform(41, s), d);
        inv += 1.0 / field.pdf(k, d);
        near += d[0] * from[0] + d[1] * from[1] + d[2] * from[2] > std::cos(0.3f);
    }
    EXPECT_NEAR(inv / draws / (4 * kPi), 1.0, 0.02);
    EXPECT_GT(near, draws / 2);
}

// The spatial lookup (a grid into the tree, then the splits that cut the point's cell) finds
// every leaf from its own records, and points beyond the records' bounds the leaf at their
// edge, as the tree's walk from its root would.
TEST(GuideField, TheLookupFindsEveryLeafFromItsRecords) {
    const float from[3] = {0.0f, 0.6f, 0.8f};
    const std::vector<GuideRecord> records = cone_records(20000, from);
    GuideField field;
    field.build(records);
    ASSERT_GT(field.distributions(), 4u);
    std::vector<int> found(field.distributions(), 0);
    for (const GuideRecord& r : records) {
        const int32_t k = field.distribution_at(r.p, r.n);
        ASSERT_GE(k, 0);
        ASSERT_LT(static_cast<size_t>(k), found.size());
        found[k] = 1;
    }
    for (size_t k = 0; k < found.size(); ++k) EXPECT_EQ(found[k], 1) << k;
    const float beyond[3] = {2.0f, 2.0f, 2.0f}, corner[3] = {0.999f, 0.999f, 0.999f};
    const float below[3] = {-3.0f, -3.0f, -3.0f}, origin[3] = {0.001f, 0.001f, 0.001f};
    EXPECT_EQ(field.distribution_at(beyond, up), field.distribution_at(corner, up));
    EXPECT_EQ(field.distribution_at(below, up), field.distribution_at(origin, up));
}

TEST(GuideField, TheSameRecordsGiveTheSameField) {
    const float from[3] = {0.0f, 0.0f, 1.0f};
    const std::vector<GuideRecord> records = cone_records(8000, from);
    GuideField a, b;
    a.build(records);
    b.build(records);
    for (int s = 0; s < 1000; ++s) {
        const float p[3] = {test_uniform(50, s), test_uniform(51, s), test_uniform(52, s)};
        ASSERT_EQ(a.distribution_at(p, up), b.distribution_at(p, up));
        const int32_t k = a.distribution_at(p, up);
        if (k < 0) continue;
        float da[3], db[3];
        a.sample(k, test_uniform(53, s), test_uniform(54, s), da);
        b.sample(k, test_uniform(53, s), test_uniform(54, s), db);
        for (int c = 0; c < 3; ++c) ASSERT_EQ(da[c], db[c]);
        ASSERT_EQ(a.pdf(k, da), b.pdf(k, db));
    }
}
