// Shading geometry at analytic-sphere hits (render/accel/sphere_points.h), one hit at a time: the
// point back on the sphere, the exact outward normal, and the tessellated sphere's tangent
// (python/patina/geometry/shapes.py: (-sin phi, 0, cos phi) at object point (cos phi, y, sin phi),
// (1, 0, 0) at the poles), turned by the sphere's frame; lanes not on a sphere keep theirs.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "render/accel/sphere_points.h"

using namespace patina;

namespace {

Vec3f rotate(const float m[9], Vec3f v) {  // rows of m: the object's axes in the world
    return Vec3f{m[0] * v.x + m[3] * v.y + m[6] * v.z, m[1] * v.x + m[4] * v.y + m[7] * v.z,
                 m[2] * v.x + m[5] * v.y + m[8] * v.z};
}

}  // namespace

TEST(SpherePoints, ExactNormalAndTheTessellatedSpheresTangent) {
    // a frame turned 40 degrees about x, then 25 about y (unit orthogonal rows)
    const double a = 40 * M_PI / 180, b = 25 * M_PI / 180;
    const double rx[3][3] = {{1, 0, 0}, {0, std::cos(a), -std::sin(a)}, {0, std::sin(a), std::cos(a)}};
    const double ry[3][3] = {{std::cos(b), 0, std::sin(b)}, {0, 1, 0}, {-std::sin(b), 0, std::cos(b)}};
    float frame[9];
    for (int axis = 0; axis < 3; ++axis)  // the world direction of object axis `axis`: column of ry rx
        for (int e = 0; e < 3; ++e) {
            double v = 0;
            for (int k = 0; k < 3; ++k) v += ry[e][k] * rx[k][axis];
            frame[3 * axis + e] = static_cast<float>(v);
        }
    SphereSet s;
    s.prim_base = 7;
    const float c[3] = {1.0f, -2.0f, 0.5f};
    s.add(c, 0.75f, frame);
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 500; ++i) {
        // an object-space point on the unit sphere (phi, y), its world hit from a ray through it
        const float phi = 3.14159f * u(rng), y = 0.999f * u(rng), ring = std::sqrt(1 - y * y);
        const Vec3f q{ring * std::cos(phi), y, ring * std::sin(phi)};
        const Vec3f n_world = rotate(frame, q);
        const Vec3f hit{c[0] + 0.75f * n_world.x, c[1] + 0.75f * n_world.y, c[2] + 0.75f * n_world.z};
        const Vec3f o{hit.x + 3.0f, hit.y + 1.0f, hit.z - 2.0f}, d{-3.0f, -1.0f, 2.0f};
        Vec3f p{0, 0, 0}, ng{0, 0, 0}, n{0, 0, 0}, t{0, 0, 0};
        sphere_points<1>(s, true, 7, o, d, 1.0f, p, ng, n, t);
        const Vec3f want_t = rotate(frame, Vec3f{-std::sin(phi), 0.0f, std::cos(phi)});
        EXPECT_NEAR(n.x, n_world.x, 2e-6f);
        EXPECT_NEAR(n.y, n_world.y, 2e-6f);
        EXPECT_NEAR(n.z, n_world.z, 2e-6f);
        EXPECT_EQ(ng.x, n.x);
        EXPECT_EQ(ng.y, n.y);
        EXPECT_EQ(ng.z, n.z);
        const Vec3f e{p.x - c[0], p.y - c[1], p.z - c[2]};
        EXPECT_NEAR(std::sqrt(dot(e, e)), 0.75f, 1e-6f);
        EXPECT_NEAR(t.x, want_t.x, 1e-5f);
        EXPECT_NEAR(t.y, want_t.y, 1e-5f);
        EXPECT_NEAR(t.z, want_t.z, 1e-5f);
    }
    // the poles: the object's x axis; a lane not on a sphere keeps its values
    Vec3f p{0, 0, 0}, ng{0, 0, 0}, n{0, 0, 0}, t{0, 0, 0};
    const Vec3f top{c[0] + 0.75f * frame[3], c[1] + 0.75f * frame[4], c[2] + 0.75f * frame[5]};
    sphere_points<1>(s, true, 7, Vec3f{top.x, top.y + 1, top.z}, Vec3f{0, -1, 0}, 1.0f, p, ng, n, t);
    EXPECT_NEAR(t.x, frame[0], 1e-3f);
    EXPECT_NEAR(t.y, frame[1], 1e-3f);
    EXPECT_NEAR(t.z, frame[2], 1e-3f);
    Vec3f keep{5, 6, 7}, keep_n = keep, keep_ng = keep, keep_t = keep;
    sphere_points<1>(s, false, 3, Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 1.0f, keep, keep_ng, keep_n, keep_t);
    EXPECT_EQ(keep.x, 5.0f);
    EXPECT_EQ(keep_t.z, 7.0f);
    EXPECT_TRUE(sphere_lanes<1>(s, 7));
    EXPECT_FALSE(sphere_lanes<1>(s, 6));
    EXPECT_FALSE(sphere_lanes<1>(s, 8));
}
