// The adaptive antialiasing's highlight pre-pass (render/antialiasing/highlights.h): the sub-pixel
// highlight of a point light on a smooth coat is found where the mirror direction of the
// light meets the camera, on a flat mirror (the analytic mirror point) and on a smooth mesh
// (the point of a sphere whose normal bisects the directions to the light and the camera);
// its size follows the roughness; it is dropped where it is not sub-pixel, not lit, not seen,
// or where the material has no sharp lobe.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "render/accel/kdtree.h"
#include "render/antialiasing/highlights.h"
#include "tests/cpp/render/antialiasing/test_scene.h"

namespace {

struct Mesh {
    std::vector<float> v, n;
    std::vector<int32_t> idx, mat;
    void quad(float x0, float y0, float x1, float y1, float z, int32_t m) {
        const int32_t b = static_cast<int32_t>(v.size() / 3);
        v.insert(v.end(), {x0, y0, z, x1, y0, z, x1, y1, z, x0, y1, z});
        for (int k = 0; k < 4; ++k) n.insert(n.end(), {0, 0, 1});
        idx.insert(idx.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
        mat.insert(mat.end(), {m, m});
    }
};

patina::Material coat(float alpha) {
    patina::Material m;
    m.coat = patina::ClearCoat{};
    m.coat->alpha = alpha;
    return m;
}

patina::Light point_light(float x, float y, float z) {
    patina::PointLight l;
    l.position[0] = x;
    l.position[1] = y;
    l.position[2] = z;
    return patina::Light{l};
}

// the centre of the pieces' union on the film, and its half-widths
struct Box {
    double x, y, hx, hy;
};
Box bounds(const std::vector<patina::AaSpot>& spots, int width) {
    double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
    for (const patina::AaSpot& s : spots) {
        const int px = s.pixel % width, py = s.pixel / width;
        x0 = std::min(x0, px + double(s.x0));
        y0 = std::min(y0, py + double(s.y0));
        x1 = std::max(x1, px + double(s.x1));
        y1 = std::max(y1, py + double(s.y1));
    }
    return {0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * (x1 - x0), 0.5 * (y1 - y0)};
}

}  // namespace

TEST(AaHighlights, OnAFlatCoatTheSpotIsAtTheMirrorPointAndItsSizeFollowsTheRoughness) {
    // a coated floor (z = 0, 4 x 4 m) seen from 2 m above, 64 x 64 pixels (32 a metre); a
    // point light at (0.5, 0.3, 1): the camera's mirror image (0, 0, -2) and the light are
    // joined by a line that meets the floor two thirds of the way, at (1/3, 0.2, 0)
    Mesh m;
    m.quad(-2, -2, 2, 2, 0, 0);
    const patina::KdTree tree = patina::build_kdtree(m.v.data(), m.v.size() / 3, m.idx.data(), m.idx.size() / 3,
                                                     patina::KdBuildOptions{});
    patina::RenderScene s = aa_test::looking_down(tree, m.idx, m.n, m.mat, 64, 64);
    s.materials = {coat(1e-3f)};
    s.lights = {point_light(0.5f, 0.3f, 1)};
    const std::vector<patina::AaSpot> sharp = patina::find_highlight_spots(s);
    ASSERT_FALSE(sharp.empty());
    const Box a = bounds(sharp, 64);
    EXPECT_NEAR(a.x, 32 + 32 * (1.0 / 3), 1e-3);
    EXPECT_NEAR(a.y, 32 - 32 * 0.2, 1e-3);
    EXPECT_GT(a.hx, 0.0);
    EXPECT_LT(a.hx, 0.5);
    for (const patina::AaSpot& p : sharp) {  // pieces inside their pixels, one a pixel
        EXPECT_GE(p.x0, 0.0f);
        EXPECT_LE(p.x1, 1.0f);
        EXPECT_LT(p.x0, p.x1);
        EXPECT_LT(p.y0, p.y1);
    }
    for (size_t k = 1; k < sharp.size(); ++k) EXPECT_LT(sharp[k - 1].pixel, sharp[k].pixel);
    // twice the roughness: twice the size, the same centre
    s.materials = {coat(2e-3f)};
    const Box b = bounds(patina::find_highlight_spots(s), 64);
    EXPECT_NEAR(b.x, a.x, 1e-3);
    EXPECT_NEAR(b.hx, 2 * a.hx, 1e-3 * a.hx + 1e-4);
    EXPECT_NEAR(b.hy, 2 * a.hy, 1e-3 * a.hy + 1e-4);
    // rough enough to be seen by the pattern: no spot; no lobe (Lambert): none
    s.materials = {coat(0.2f)};
    EXPECT_TRUE(patina::find_highlight_spots(s).empty());
    s.materials = {patina::Material{}};
    EXPECT_TRUE(patina::find_highlight_spots(s).empty());
}

TEST(AaHighlights, AShadowedOrHiddenSpotIsDropped) {
    Mesh m;
    m.quad(-2, -2, 2, 2, 0, 0);
    m.quad(0.4f, 0.2f, 0.5f, 0.35f, 0.7f, 1);  // a small card between the mirror point and the light
    const patina::KdTree tree = patina::build_kdtree(m.v.data(), m.v.size() / 3, m.idx.data(), m.idx.size() / 3,
                                                     patina::KdBuildOptions{});
    patina::RenderScene s = aa_test::looking_down(tree, m.idx, m.n, m.mat, 64, 64);
    patina::Material lambert;
    s.materials = {coat(1e-3f), lambert};
    s.lights = {point_light(0.5f, 0.3f, 1)};
    // the light's ray from (1/3, 0.2, 0) crosses z = 0.7 at (0.45, 0.27): on the card
    EXPECT_TRUE(patina::find_highlight_spots(s).empty());
    // the card over the mirror point, seen from the camera: (1/3, 0.2, 0) is seen through
    // (0.22, 0.13) at z = 0.7
    Mesh hidden;
    hidden.quad(-2, -2, 2, 2, 0, 0);
    hidden.quad(0.17f, 0.08f, 0.27f, 0.18f, 0.7f, 1);
    const patina::KdTree tree2 = patina::build_kdtree(hidden.v.data(), hidden.v.size() / 3, hidden.idx.data(),
                                                      hidden.idx.size() / 3, patina::KdBuildOptions{});
    patina::RenderScene s2 = aa_test::looking_down(tree2, hidden.idx, hidden.n, hidden.mat, 64, 64);
    s2.materials = s.materials;
    s2.lights = s.lights;
    EXPECT_TRUE(patina::find_highlight_spots(s2).empty());
}

TEST(AaHighlights, OnASmoothSphereTheSpotIsWhereTheNormalBisectsLightAndCamera) {
    // a unit sphere (48 x 96 quads, normals the positions) at (0, 0, -2), so 4 m from the
    // camera, 128 x 128 pixels; a point light at (3, 0, 2): the highlight lies in the plane
    // y = 0, at the angle phi (from +z towards +x) where the normal bisects the directions
    constexpr int rings = 48, segments = 96;
    constexpr double pi = 3.14159265358979323846;
    Mesh m;
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j <= segments; ++j) {
            const double th = pi * i / rings, ph = 2 * pi * j / segments;
            const float x = float(std::sin(th) * std::cos(ph)), y = float(std::sin(th) * std::sin(ph)),
                        z = float(std::cos(th));
            m.v.insert(m.v.end(), {x, y, z - 2});
            m.n.insert(m.n.end(), {x, y, z});
        }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const int32_t a = i * (segments + 1) + j, b = a + 1, c = a + segments + 1, d = c + 1;
            m.idx.insert(m.idx.end(), {a, c, d, a, d, b});
            m.mat.insert(m.mat.end(), {0, 0});
        }
    const patina::KdTree tree = patina::build_kdtree(m.v.data(), m.v.size() / 3, m.idx.data(), m.idx.size() / 3,
                                                     patina::KdBuildOptions{});
    patina::RenderScene s = aa_test::looking_down(tree, m.idx, m.n, m.mat, 128, 128);
    s.materials = {coat(1e-3f)};
    s.lights = {point_light(3, 0, 2)};
    // the bisecting point by bisection on phi: n(phi) . (l - v) = 0 with l, v the unit
    // directions to the light and the camera
    const auto mismatch = [](double ph) {
        const double px = std::sin(ph), pz = std::cos(ph) - 2;
        double lx = 3 - px, lz = 2 - pz, vx = -px, vz = 2 - pz;
        const double ll = std::hypot(lx, lz), lv = std::hypot(vx, vz);
        lx /= ll, lz /= ll, vx /= lv, vz /= lv;
        return std::sin(ph) * (lx - vx) + std::cos(ph) * (lz - vz);
    };
    double lo = 0, hi = pi / 2;
    for (int k = 0; k < 60; ++k) (mismatch(0.5 * (lo + hi)) > 0 ? hi : lo) = 0.5 * (lo + hi);
    const double ph = 0.5 * (lo + hi), px = std::sin(ph), pz = std::cos(ph) - 2;
    const double film_x = (px / (2 - pz) / 0.5 + 1) * 64;
    const std::vector<patina::AaSpot> spots = patina::find_highlight_spots(s);
    ASSERT_FALSE(spots.empty());
    const Box b = bounds(spots, 128);
    EXPECT_NEAR(b.x, film_x, 0.05);  // the mesh is not the sphere: its facets' sagitta
    EXPECT_NEAR(b.y, 64.0, 0.05);
    EXPECT_LT(b.hx, 0.5);
    EXPECT_LT(b.hy, 0.5);
    // the same sphere analytic (render/accel/spheres.h, no triangles): the spot where the exact
    // normal bisects, of the tessellated one's size
    patina::KdTree exact = patina::build_kdtree(nullptr, 0, nullptr, 0, patina::KdBuildOptions{});
    const float centre[3] = {0, 0, -2}, frame[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    exact.spheres.add(centre, 1.0f, frame);
    const std::vector<int32_t> none, one = {0};
    const std::vector<float> no_normals;
    patina::RenderScene a = aa_test::looking_down(exact, none, no_normals, one, 128, 128);
    a.materials = s.materials;
    a.lights = s.lights;
    const std::vector<patina::AaSpot> round = patina::find_highlight_spots(a);
    ASSERT_FALSE(round.empty());
    const Box e = bounds(round, 128);
    EXPECT_NEAR(e.x, film_x, 0.005);
    EXPECT_NEAR(e.y, 64.0, 0.005);
    EXPECT_NEAR(e.hx, b.hx, 0.1 * b.hx);
    EXPECT_NEAR(e.hy, b.hy, 0.1 * b.hy);
}
