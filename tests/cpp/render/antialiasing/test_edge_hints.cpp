// The adaptive antialiasing's geometric pre-pass (render/antialiasing/edge_hints.h): a segment marks
// the pixels it crosses with the zones it crosses in each orientation, of a mesh only the
// feature edges are projected, and a point light's shadow of an edge is projected where it
// falls; any thread count gives the same hints.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include "render/accel/kdtree.h"
#include "render/antialiasing/edge_hints.h"
#include "tests/cpp/render/antialiasing/test_scene.h"

namespace {

patina::AaEdgeHints empty_hints(int w, int h) {
    patina::AaEdgeHints hints;
    hints.resize(w, h);
    return hints;
}

}  // namespace

TEST(AaEdgeHints, AVerticalSegmentMarksItsColumnWithTheZoneItCrosses) {
    patina::AaEdgeHints h = empty_hints(8, 8);
    std::vector<double> crossings;  // rasterise_edge's scratch
    patina::rasterise_edge(h, 3.3f, 1.0f, 3.3f, 5.0f, 2.0f, 2.0f, 0.5f, 0.5f, crossings);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const size_t i = static_cast<size_t>(y) * 8 + x;
            const bool on = x == 3 && y >= 1 && y < 5;
            EXPECT_EQ(h.zones[0][i], on ? 1u << 1 : 0u) << x << " " << y;  // u = 0.3: zone 1
            EXPECT_EQ(h.zones[1][i], on ? 0x1Fu : 0u) << x << " " << y;    // turned: across every zone
            EXPECT_EQ(std::isfinite(h.nearest[i]), on);
            if (on) {
                EXPECT_GE(h.nearest[i], 2.0f);  // at least its depth along the view axis
            }
        }
}

TEST(AaEdgeHints, AnObliqueSegmentMarksTheZonesOfItsPartInEachPixel) {
    patina::AaEdgeHints h = empty_hints(4, 4);
    // from (1.15, 1.0) to (1.55, 2.0): inside pixel (1, 1), u from 0.15 to 0.55, of which
    // between the zigzags' rows v = 1/4 and 3/4 u from 0.25 to 0.45: zones 1 and 2 (not 0)
    std::vector<double> crossings;  // rasterise_edge's scratch
    patina::rasterise_edge(h, 1.15f, 1.0f, 1.55f, 2.0f, 1.0f, 1.0f, 0.5f, 0.5f, crossings);
    EXPECT_EQ(h.zones[0][1 * 4 + 1], 0x06u);
    // turned, (u, v) = (1 - y, x): v = x in [1/4, 3/4] from y = 0.25 to 1, u from 0.75 to 0
    EXPECT_EQ(h.zones[1][1 * 4 + 1], 0x0Fu);
    int marked = 0;
    for (const uint8_t z : h.zones[0]) marked += z != 0;
    EXPECT_EQ(marked, 1);
}

TEST(AaEdgeHints, ASegmentOutsideTheImageMarksNothing) {
    patina::AaEdgeHints h = empty_hints(4, 4);
    std::vector<double> crossings;  // rasterise_edge's scratch
    patina::rasterise_edge(h, -3.0f, -1.0f, 9.0f, -0.5f, 1.0f, 1.0f, 0.5f, 0.5f, crossings);
    for (const uint8_t z : h.zones[0]) EXPECT_EQ(z, 0u);
}

TEST(AaEdgeHints, AScratchKeptFromEdgeToEdgeMarksWhatAFreshOneWould) {
    // a long oblique edge, then a short one: the second must not see the first's crossings
    patina::AaEdgeHints kept = empty_hints(8, 8), fresh = empty_hints(8, 8);
    std::vector<double> crossings;
    patina::rasterise_edge(kept, 0.2f, 0.3f, 7.7f, 6.1f, 1.0f, 3.0f, 0.5f, 0.5f, crossings);
    patina::rasterise_edge(kept, 5.2f, 1.1f, 5.6f, 1.9f, 2.0f, 2.0f, 0.5f, 0.5f, crossings);
    for (const auto& [x0, y0, x1, y1, z0, z1] : {std::array<float, 6>{0.2f, 0.3f, 7.7f, 6.1f, 1.0f, 3.0f},
                                                 std::array<float, 6>{5.2f, 1.1f, 5.6f, 1.9f, 2.0f, 2.0f}}) {
        std::vector<double> own;
        patina::rasterise_edge(fresh, x0, y0, x1, y1, z0, z1, 0.5f, 0.5f, own);
    }
    EXPECT_EQ(kept.zones[0], fresh.zones[0]);
    EXPECT_EQ(kept.zones[1], fresh.zones[1]);
    EXPECT_EQ(std::memcmp(kept.nearest.data(), fresh.nearest.data(), kept.nearest.size() * sizeof(float)), 0);
}

TEST(AaEdgeHints, OfAMeshOnlyTheFeatureEdgesAreProjected) {
    // a square of two triangles facing a camera 2 m away, its boundary inside the image:
    // its four sides are boundary edges, the shared diagonal (same material, flat) is not
    const std::vector<float> v = {-0.5f, -0.5f, 0, 0.5f, -0.5f, 0, 0.5f, 0.5f, 0, -0.5f, 0.5f, 0};
    const std::vector<int32_t> idx = {0, 1, 2, 0, 2, 3};
    const std::vector<int32_t> mat = {0, 0};
    const std::vector<float> n = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    patina::KdTree tree;
    const auto set_triangles = [&](const std::vector<float>& pos, const std::vector<int32_t>& tris) {
        tree.triangles.clear();  // the positions the tree holds, corner by corner
        for (const int32_t k : tris) tree.triangles.insert(tree.triangles.end(), &pos[3 * k], &pos[3 * k] + 3);
    };
    set_triangles(v, idx);
    tree.normals = {0, 0, 1, 0, 0, 1};
    // looking down -z, 32 x 32, the square 0.5 / (2 tan) = half the half height
    patina::RenderScene s = aa_test::looking_down(tree, idx, n, mat, 32, 32);
    const patina::AaEdgeHints h = patina::project_feature_edges(s, 0.1f);
    // the square spans film 8 .. 24 on both axes: its sides on x = 8, x = 24, y = 8, y = 24
    const auto marked = [&](int x, int y) {
        const size_t i = static_cast<size_t>(y) * 32 + x;
        return h.zones[0][i] != 0 || h.zones[1][i] != 0;
    };
    EXPECT_TRUE(marked(8, 16) || marked(7, 16));
    EXPECT_TRUE(marked(16, 8) || marked(16, 7));
    EXPECT_TRUE(marked(23, 16) || marked(24, 16));
    EXPECT_FALSE(marked(16, 15));  // on the diagonal (film x + y = 32): no feature
    EXPECT_FALSE(marked(12, 12));
    EXPECT_FALSE(marked(2, 2));    // outside the square
    EXPECT_NEAR(h.nearest[16 * 32 + 8] < INFINITY ? h.nearest[16 * 32 + 8] : h.nearest[16 * 32 + 7], 2.06f, 0.05f);
    // a crease: the same square folded along its diagonal (split normals) marks the diagonal
    const std::vector<float> v2 = {-0.5f, -0.5f, 0, 0.5f, -0.5f, 0, 0.5f, 0.5f, 0,
                                   -0.5f, -0.5f, 0, 0.5f, 0.5f, 0,  -0.5f, 0.5f, 0};
    const std::vector<int32_t> idx2 = {0, 1, 2, 3, 4, 5};
    const std::vector<float> n2 = {0.6f,  0, 0.8f, 0.6f,  0, 0.8f, 0.6f,  0, 0.8f,
                                   -0.6f, 0, 0.8f, -0.6f, 0, 0.8f, -0.6f, 0, 0.8f};
    set_triangles(v2, idx2);
    s.indices = idx2.data();
    s.normals = n2.data();
    const patina::AaEdgeHints folded = patina::project_feature_edges(s, 0.1f);
    EXPECT_NE(folded.zones[0][15 * 32 + 16], 0u);
    EXPECT_EQ(folded.zones[0][20 * 32 + 12], 0u);  // away from the diagonal and the sides
    // the mesh's edges are kept for the next render of the same geometry (by content): the
    // flat square again, after the folded one, gives the flat square's hints, not the fold's
    set_triangles(v, idx);
    s.indices = idx.data();
    s.normals = n.data();
    const patina::AaEdgeHints again = patina::project_feature_edges(s, 0.1f);
    EXPECT_EQ(again.zones[0], h.zones[0]);
    EXPECT_EQ(again.zones[1], h.zones[1]);
    EXPECT_EQ(patina::project_feature_edges(s, 0.1f).zones[0], h.zones[0]);  // and once more, kept
}

TEST(AaEdgeHints, APointLightsShadowOfAStripIsMarkedWhereItFalls) {
    // a floor (z = 0, 4 x 4 m) and above it a strip x in [-0.06, 0.04], y in [-0.3, 0.3] at
    // z = 0.5, both facing a camera 2 m above the floor (32 x 32, 16 pixels a metre on the
    // floor); a point light at (0.5, 0, 1) casts the strip's shadow at twice its size, x in
    // [-0.62, -0.42], y in [-0.6, 0.6]: its long sides on film x = 6.08 and 9.28, from film
    // y = 6.4 to 25.6 (the strip itself is at film x 14.7 .. 16.9)
    const std::vector<float> v = {-2, -2, 0, 2, -2, 0, 2, 2, 0, -2, 2, 0,
                                  -0.06f, -0.3f, 0.5f, 0.04f, -0.3f, 0.5f, 0.04f, 0.3f, 0.5f, -0.06f, 0.3f, 0.5f};
    const std::vector<int32_t> idx = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    const std::vector<int32_t> mat = {0, 0, 1, 1};
    std::vector<float> n;
    for (int k = 0; k < 8; ++k) n.insert(n.end(), {0, 0, 1});
    const patina::KdTree tree = patina::build_kdtree(v.data(), 8, idx.data(), 4, patina::KdBuildOptions{});
    patina::RenderScene s = aa_test::looking_down(tree, idx, n, mat, 32, 32);
    const auto marked = [](const patina::AaEdgeHints& h, int x, int y) {
        const size_t i = static_cast<size_t>(y) * 32 + x;
        return h.zones[0][i] != 0 || h.zones[1][i] != 0;
    };
    const patina::AaEdgeHints dark = patina::project_feature_edges(s, 0.1f);
    EXPECT_TRUE(marked(dark, 15, 16) || marked(dark, 14, 16));  // the strip's side
    EXPECT_FALSE(marked(dark, 6, 16));
    EXPECT_FALSE(marked(dark, 9, 16));
    patina::PointLight light;
    light.position[0] = 0.5f;
    light.position[2] = 1;
    s.lights.push_back(patina::Light{light});
    const patina::AaEdgeHints lit = patina::project_feature_edges(s, 0.1f);
    for (int y = 8; y < 25; ++y) {
        EXPECT_TRUE(marked(lit, 6, y)) << y;  // the shadow's sides
        EXPECT_TRUE(marked(lit, 9, y)) << y;
        EXPECT_FALSE(marked(lit, 7, y)) << y;  // inside the shadow
        EXPECT_FALSE(marked(lit, 8, y)) << y;
        EXPECT_FALSE(marked(lit, 3, y)) << y;  // outside it
        EXPECT_FALSE(marked(lit, 12, y)) << y;
    }
    EXPECT_EQ(lit.zones[0][16 * 32 + 6], 1u << 0);  // x = 6.08: zone 0 (u in [0, 0.2])
    EXPECT_EQ(lit.zones[0][16 * 32 + 9], 1u << 1);  // x = 9.28: zone 1
    EXPECT_NEAR(lit.nearest[16 * 32 + 6], 2.0f * std::sqrt(1 + 0.62f * 0.62f / 4), 0.03f);  // on the floor
    EXPECT_TRUE(marked(lit, 15, 16) || marked(lit, 14, 16));  // the strip is still there
}

TEST(AaEdgeHints, AnyThreadCountGivesTheSameHints) {
    // a folded floor of 48 x 48 quads (creases where the fold changes, 7000 edges) under a
    // strip and a point light: feature edges and shadows from every part of the edge list
    constexpr int n = 48;
    std::vector<float> v;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float x = -2 + 4.0f * i / n, y = -2 + 4.0f * j / n;
            v.insert(v.end(), {x, y, 0.1f * std::fabs(std::sin(3.0f * x)) * ((i / 4 + j / 5) % 2)});
        }
    std::vector<int32_t> idx;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            idx.insert(idx.end(), {a, b, d, a, d, c});
        }
    const int32_t base = static_cast<int32_t>(v.size() / 3);
    v.insert(v.end(), {-0.06f, -0.3f, 0.5f, 0.04f, -0.3f, 0.5f, 0.04f, 0.3f, 0.5f, -0.06f, 0.3f, 0.5f});
    idx.insert(idx.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    const size_t tris = idx.size() / 3;
    std::vector<float> normals;
    for (size_t k = 0; k < v.size() / 3; ++k) normals.insert(normals.end(), {0, 0, 1});
    const std::vector<int32_t> mat(tris, 0);
    const patina::KdTree tree =
        patina::build_kdtree(v.data(), v.size() / 3, idx.data(), tris, patina::KdBuildOptions{});
    patina::RenderScene s = aa_test::looking_down(tree, idx, normals, mat, 64, 48);
    patina::PointLight light;
    light.position[0] = 0.5f;
    light.position[2] = 1;
    s.lights.push_back(patina::Light{light});
    const patina::AaEdgeHints one = patina::project_feature_edges(s, 0.001f, 1);
    int marked = 0;
    for (const uint8_t z : one.zones[0]) marked += z != 0;
    EXPECT_GT(marked, 100);
    for (const int threads : {2, 3, 8}) {
        const patina::AaEdgeHints more = patina::project_feature_edges(s, 0.001f, threads);
        EXPECT_EQ(more.zones[0], one.zones[0]) << threads;
        EXPECT_EQ(more.zones[1], one.zones[1]) << threads;
        EXPECT_EQ(0, std::memcmp(more.nearest.data(), one.nearest.data(), one.nearest.size() * sizeof(float)))
            << threads;
    }
}
