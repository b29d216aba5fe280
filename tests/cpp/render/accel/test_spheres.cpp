// The analytic spheres (render/accel/spheres.h, sphere_test.h) through every trace entry
// point: hits, misses, grazing rays, origins inside, far and small spheres against a
// double-precision reference; the same bits at every width, in packets (kd-tree) and single
// rays (BVH); closest hits among triangles and spheres; rays and shadow rays leaving a
// sphere's surface do not hit it at their origin.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "core/cpu.h"
#include "render/accel/bvh.h"
#include "render/accel/kdtree.h"
#include "render/accel/spheres.h"
#include "render/accel/trace_kernels.h"
#include "tests/cpp/render/accel/trace_test_scenes.h"

using namespace patina;
using namespace trace_test;

namespace {

struct Ball {
    double c[3], r;
};

struct Hits {
    std::vector<float> t, u, v;
    std::vector<int32_t> prim;
    explicit Hits(size_t n) : t(n), u(n), v(n), prim(n) {}
    HitBatch batch() { return HitBatch{t.data(), prim.data(), u.data(), v.data()}; }
};

// A kd-tree and a BVH over the mesh's triangles with the balls as analytic spheres.
struct Scene {
    KdTree tree;
    Bvh bvh;
    std::vector<Ball> balls;
    Scene(const Mesh& m, const std::vector<Ball>& b) : balls(b) {
        tree = build_kdtree(m.v.data(), m.v.size() / 3, m.f.data(), m.triangles(), KdBuildOptions{});
        bvh = build_bvh(tree.triangles.data(), tree.triangle_count());
        tree.spheres.prim_base = static_cast<int32_t>(m.triangles());
        const float frame[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        for (const Ball& x : b) {
            const float c[3] = {float(x.c[0]), float(x.c[1]), float(x.c[2])};
            tree.spheres.add(c, float(x.r), frame);
        }
        bvh.spheres = tree.spheres;
    }
    Hits trace(const Rays& rays, int width, bool through_bvh, float tmin = 0.0f) const {
        Hits h(rays.size());
        const RayBatch batch{rays.o.data(), rays.d.data(), tmin, nullptr, kInf};
        if (through_bvh) trace_intersect(bvh, batch, h.batch(), rays.size(), width, 1);
        else trace_intersect(tree, batch, h.batch(), rays.size(), width, 1);
        return h;
    }
    std::vector<uint8_t> occluded(const Rays& rays, const std::vector<float>& tmax, int width, bool through_bvh,
                                  float tmin = 0.0f) const {
        std::vector<uint8_t> blocked(rays.size());
        const RayBatch batch{rays.o.data(), rays.d.data(), tmin, tmax.data(), 0.0f};
        if (through_bvh) trace_occluded(bvh, batch, blocked.data(), rays.size(), width, 1);
        else trace_occluded(tree, batch, blocked.data(), rays.size(), width, 1);
        return blocked;
    }
};

// The ray (float o, d taken exactly) against one ball in double: the least root > 0, and
// whether hit or miss is certain (the discriminant clear of float rounding: the float test
// may decide a grazing ray either way).
struct Reference {
    double t = kInf;
    int ball = -1;
    bool certain = true;
};

Reference reference(const std::vector<Ball>& balls, const float* o, const float* d) {
    Reference out;
    for (size_t k = 0; k < balls.size(); ++k) {
        const Ball& s = balls[k];
        // the float sphere the tracer holds
        const double c[3] = {double(float(s.c[0])), double(float(s.c[1])), double(float(s.c[2]))}, r = float(s.r);
        const double f[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
        const double a = double(d[0]) * d[0] + double(d[1]) * d[1] + double(d[2]) * d[2];
        const double b = f[0] * d[0] + f[1] * d[1] + f[2] * d[2];
        double l2 = 0, f2 = 0;
        for (int i = 0; i < 3; ++i) {
            const double l = f[i] - b / a * d[i];
            l2 += l * l;
            f2 += f[i] * f[i];
        }
        const double disc = r * r - l2;
        // float rounding of the closest approach: a few ulps of |f| and r
        if (std::fabs(disc) < 1e-5 * (f2 + r * r)) out.certain = false;
        if (disc < 0) continue;
        const double q = -(b + std::copysign(std::sqrt(a * disc), b));
        double t0 = (f2 - r * r) / q, t1 = q / a;
        if (t0 > t1) std::swap(t0, t1);
        const double t = t0 > 0 ? t0 : t1;
        if (t > 0 && t < out.t) {
            out.t = t;
            out.ball = static_cast<int>(k);
        }
    }
    return out;
}

// A unit sphere at the origin, a small near one, a large far one, a small far one.
std::vector<Ball> assorted() {
    return {{{0, 0, 0}, 1.0}, {{0.5, 2.0, -0.3}, 0.01}, {{3.0, -200.0, -1000.0}, 50.0}, {{300.0, 20.0, 0.0}, 1e-3}};
}

// Random rays from a cube around the unit sphere (many start inside it), rays aimed at each
// ball's centre from afar, and rays grazing each ball (aimed at its rim, just inside and out).
Rays assorted_rays(const std::vector<Ball>& balls) {
    Rays rays = random_rays(4000, 7, 1.5f);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (const Ball& s : balls) {
        for (int i = 0; i < 200; ++i) {
            const std::array<double, 3> from = {5 * u(rng), 5 * u(rng), 5 + 5 * u(rng)};
            const std::array<double, 3> to = {s.c[0] + 0.5 * s.r * u(rng), s.c[1] + 0.5 * s.r * u(rng), s.c[2]};
            rays.add({float(from[0]), float(from[1]), float(from[2])},
                     {float(to[0] - from[0]), float(to[1] - from[1]), float(to[2] - from[2])});
            // grazing: the rim point at angle a, scaled by 1 +- 1e-3
            const double ang = 3.14159 * u(rng), scale = 1 + 1e-3 * u(rng);
            const std::array<double, 3> rim = {s.c[0] + scale * s.r * std::cos(ang), s.c[1] + scale * s.r * std::sin(ang),
                                               s.c[2]};
            rays.add({float(rim[0]), float(rim[1]), float(rim[2] + 10 * s.r + 4)}, {0.0f, 0.0f, -1.0f});
        }
    }
    return rays;
}

bool inside_any(const std::vector<Ball>& balls, const float* o) {
    for (const Ball& s : balls) {
        const double dx = o[0] - s.c[0], dy = o[1] - s.c[1], dz = o[2] - s.c[2];
        if (dx * dx + dy * dy + dz * dz < s.r * s.r) return true;
    }
    return false;
}

TEST(Spheres, HitsMatchDoublePrecision) {
    const std::vector<Ball> balls = assorted();
    const Scene scene(Mesh{}, balls);
    const Rays rays = assorted_rays(balls);
    const Hits h = scene.trace(rays, 1, false);
    int hits = 0, inside = 0, grazing = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const Reference want = reference(balls, &rays.o[3 * i], &rays.d[3 * i]);
        if (!want.certain) {
            ++grazing;
            if (h.prim[i] < 0 || want.ball < 0) continue;  // either answer is right
        }
        ASSERT_EQ(h.prim[i], want.ball) << "ray " << i << " (reference t " << want.t << ", got " << h.t[i] << ")";
        if (want.ball < 0) continue;
        ++hits;
        inside += inside_any(balls, &rays.o[3 * i]) ? 1 : 0;
        // t within a few float ulps of the distances involved (grazing rays: of the chord's root)
        const double tol = want.certain ? 4e-6 * want.t + 1e-6 : 2e-3 * want.t;
        EXPECT_NEAR(h.t[i], want.t, tol) << "ray " << i;
    }
    EXPECT_GT(hits, 1500);
    EXPECT_GT(inside, 300);
    EXPECT_GT(grazing, 20);
}

// Every width, kd-tree packets and BVH single rays: the same prim and t bits, and any hit
// agreeing with the closest hit; triangles (a soup) among the spheres.
TEST(Spheres, EveryWidthAndBothStructuresGiveTheSameBits) {
    const std::vector<Ball> balls = assorted();
    const Mesh m = soup(300, 11);
    const Scene scene(m, balls);
    Rays rays = assorted_rays(balls);
    rays.o.resize(3 * (rays.size() - 5));  // the last packet partial at every width
    rays.d.resize(rays.o.size());
    const Hits want = scene.trace(rays, 1, false);
    std::vector<float> tmax(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) tmax[i] = want.prim[i] >= 0 ? want.t[i] * (i % 2 ? 1.01f : 0.99f) : 1e4f;
    int on_spheres = 0, on_triangles = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        on_spheres += scene.tree.spheres.owns(want.prim[i]) ? 1 : 0;
        on_triangles += want.prim[i] >= 0 && !scene.tree.spheres.owns(want.prim[i]) ? 1 : 0;
    }
    EXPECT_GT(on_spheres, 1000);
    EXPECT_GT(on_triangles, 300);
    for (bool through_bvh : {false, true})
        for (int w : {1, 4, 8, 16}) {
            if (!width_supported(w)) continue;
            const Hits got = scene.trace(rays, w, through_bvh);
            const std::vector<uint8_t> blocked = scene.occluded(rays, tmax, w, through_bvh);
            for (size_t i = 0; i < rays.size(); ++i) {
                ASSERT_EQ(got.prim[i], want.prim[i]) << "width " << w << (through_bvh ? " bvh" : " kd") << " ray " << i;
                ASSERT_EQ(got.t[i], want.t[i]) << "width " << w << (through_bvh ? " bvh" : " kd") << " ray " << i;
                ASSERT_EQ(blocked[i] != 0, want.prim[i] >= 0 && i % 2 == 1)
                    << "any hit, width " << w << (through_bvh ? " bvh" : " kd") << " ray " << i;
            }
        }
}

// Shadow rays skip a sphere their line passes at a distance (sphere_test.h, passes_near):
// the answer must stay the quadratic's. Rays from near and far (coordinates to 10^3) aimed at
// the spheres' silhouettes (grazing, within 10^-3 of the radius either side), their segments
// ending a hair (2^-20) before or after the closest hit, at infinity, or empty: blocked exactly
// where the closest hit lies within the segment, at every width and through both structures.
TEST(Spheres, ShadowRaysEndingAtASpheresEdgeKeepTheQuadraticsAnswer) {
    const std::vector<Ball> balls = {{{0.5, 1.0, -0.5}, 0.8}, {{300.0, -20.0, 150.0}, 3.0}, {{2.0, 0.0, 2.0}, 0.01}};
    const Scene scene(Mesh{}, balls);
    std::mt19937 rng(21);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Rays rays;
    for (int i = 0; i < 6000; ++i) {
        const Ball& s = balls[i % balls.size()];
        const double reach = (i / 3) % 2 ? 1e3 : 5.0;  // origins near the sphere or far away
        const double o[3] = {s.c[0] + reach * u(rng), s.c[1] + reach * u(rng), s.c[2] + reach * u(rng)};
        // n: a random direction square to the sphere's centre as seen from o
        double n[3] = {g(rng), g(rng), g(rng)}, view[3], lv = 0, along = 0, ln = 0;
        for (int a = 0; a < 3; ++a) {
            view[a] = s.c[a] - o[a];
            lv += view[a] * view[a];
        }
        for (int a = 0; a < 3; ++a) along += n[a] * view[a] / lv;
        for (int a = 0; a < 3; ++a) {
            n[a] -= along * view[a];
            ln += n[a] * n[a];
        }
        ln = std::sqrt(ln);
        const double at = s.r * (1.0 + 1e-3 * u(rng));  // a point by the silhouette
        double d[3], len = 0;
        for (int a = 0; a < 3; ++a) {
            d[a] = s.c[a] + at * n[a] / ln - o[a];
            len += d[a] * d[a];
        }
        len = std::sqrt(len);
        rays.add({float(o[0]), float(o[1]), float(o[2])}, {float(d[0] / len), float(d[1] / len), float(d[2] / len)});
    }
    const float tmin = 1e-4f;
    const Hits closest = scene.trace(rays, 1, true, tmin);
    std::vector<float> tmax(rays.size());
    int hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const float t = closest.prim[i] >= 0 ? closest.t[i] : 1e3f;
        hits += closest.prim[i] >= 0 ? 1 : 0;
        const float ends[4] = {t * (1.0f - 0x1p-20f), t * (1.0f + 0x1p-20f), kInf, tmin / 2};
        tmax[i] = ends[(i / 7) % 4];
    }
    EXPECT_GT(hits, 1000);
    EXPECT_LT(hits, 5000);
    for (bool through_bvh : {false, true})
        for (int w : {1, 4, 8, 16}) {
            if (!width_supported(w)) continue;
            const std::vector<uint8_t> blocked = scene.occluded(rays, tmax, w, through_bvh, tmin);
            for (size_t i = 0; i < rays.size(); ++i)
                ASSERT_EQ(blocked[i] != 0, closest.prim[i] >= 0 && closest.t[i] < tmax[i])
                    << "width " << w << (through_bvh ? " bvh" : " kd") << " ray " << i << " tmax " << tmax[i];
        }
}

// The closest of triangles and spheres: an icosphere beside and through the analytic spheres
// against brute force (triangles in double) and the sphere reference.
TEST(Spheres, ClosestOfTrianglesAndSpheres) {
    Mesh m = icosphere(2);
    for (size_t i = 0; i < m.v.size(); i += 3) m.v[i] += 0.8f;  // overlaps the unit sphere
    const std::vector<Ball> balls = {{{0, 0, 0}, 1.0}, {{-0.6, 0.9, 0.2}, 0.3}};
    const Scene scene(m, balls);
    const Rays rays = random_rays(3000, 5, 2.5f);
    for (bool through_bvh : {false, true}) {
        const Hits h = scene.trace(rays, width_supported(8) ? 8 : 1, through_bvh);
        int spheres = 0, triangles = 0;
        for (size_t i = 0; i < rays.size(); ++i) {
            const auto [tt, tri] = brute_force(m, &rays.o[3 * i], &rays.d[3 * i]);
            const Reference s = reference(balls, &rays.o[3 * i], &rays.d[3 * i]);
            if (!s.certain || (tri >= 0 && s.ball >= 0 && std::fabs(tt - s.t) < 1e-4 * tt)) continue;  // a near tie
            if (s.ball >= 0 && s.t < tt) {
                ++spheres;
                ASSERT_EQ(h.prim[i], scene.tree.spheres.prim_base + s.ball) << "ray " << i;
                EXPECT_NEAR(h.t[i], s.t, 4e-6 * s.t) << "ray " << i;
            } else if (tri >= 0) {
                ++triangles;
                ASSERT_EQ(h.prim[i] >= 0 && !scene.tree.spheres.owns(h.prim[i]), true) << "ray " << i;
                EXPECT_NEAR(h.t[i], tt, 1e-5 * tt) << "ray " << i;
            } else {
                ASSERT_EQ(h.prim[i], -1) << "ray " << i;
            }
        }
        EXPECT_GT(spheres, 100);
        EXPECT_GT(triangles, 100);
    }
}

// Rays from points on the sphere (as the shading points are: c + r n in float): leaving it
// (the outer hemisphere) they and their shadow rays see nothing; entering it they find the far
// side at the chord's length 2 r cos theta. With tmin 0 and no offset, at every width.
TEST(Spheres, RaysLeavingTheSurfaceDoNotHitItAgain) {
    const std::vector<Ball> balls = {{{0.3, -0.2, 0.1}, 0.7}, {{40.0, 10.0, -30.0}, 2.5}};
    const Scene scene(Mesh{}, balls);
    std::mt19937 rng(9);
    std::normal_distribution<double> g;
    Rays out, in;
    std::vector<double> chord, slack;
    for (const Ball& s : balls)
        for (int i = 0; i < 2000; ++i) {
            double n[3] = {g(rng), g(rng), g(rng)}, w[3] = {g(rng), g(rng), g(rng)};
            const double ln = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            const double lw = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
            double cosine = 0;
            for (int a = 0; a < 3; ++a) {
                n[a] /= ln;
                w[a] /= lw;
                cosine += n[a] * w[a];
            }
            if (std::fabs(cosine) < 1e-3) continue;
            const float sgn = cosine > 0 ? 1.0f : -1.0f;  // w into the outer hemisphere
            const std::array<float, 3> p = {float(float(s.c[0]) + float(s.r) * float(n[0])),
                                            float(float(s.c[1]) + float(s.r) * float(n[1])),
                                            float(float(s.c[2]) + float(s.r) * float(n[2]))};
            out.add(p, {sgn * float(w[0]), sgn * float(w[1]), sgn * float(w[2])});
            in.add(p, {-sgn * float(w[0]), -sgn * float(w[1]), -sgn * float(w[2])});
            chord.push_back(2 * s.r * std::fabs(cosine));
            // the stored point is off the sphere by its rounding (~2^-23 (|c|_1 + 3 r)), which
            // moves the far side by that over the cosine
            slack.push_back(4 * 0x1p-23 * (std::fabs(s.c[0]) + std::fabs(s.c[1]) + std::fabs(s.c[2]) + 3 * s.r) /
                                std::fabs(cosine) +
                            1e-6 * s.r);
        }
    const std::vector<float> far(out.size(), 1e4f);
    for (bool through_bvh : {false, true})
        for (int w : {1, 4, 8, 16}) {
            if (!width_supported(w)) continue;
            const Hits leaving = scene.trace(out, w, through_bvh), entering = scene.trace(in, w, through_bvh);
            const std::vector<uint8_t> shadow = scene.occluded(out, far, w, through_bvh);
            for (size_t i = 0; i < out.size(); ++i) {
                ASSERT_EQ(leaving.prim[i], -1) << "width " << w << " ray " << i << " hit at " << leaving.t[i];
                ASSERT_EQ(shadow[i], 0) << "width " << w << " shadow ray " << i;
                ASSERT_GE(entering.prim[i], 0) << "width " << w << " ray " << i;
                EXPECT_NEAR(entering.t[i], chord[i], slack[i]) << "ray " << i;
            }
        }
}

// hit_normals: a sphere's outward unit normal at the hit, a triangle's from its winding.
TEST(Spheres, HitNormalsPointOutwards) {
    const std::vector<Ball> balls = {{{1, 2, 3}, 0.5}};
    const Scene scene(Mesh{}, balls);
    const Rays rays = random_rays(500, 2, 0.25f);
    Rays shifted = rays;
    for (size_t i = 0; i < shifted.o.size(); ++i) shifted.o[i] += float(balls[0].c[i % 3]);
    Hits h = scene.trace(shifted, 1, false);
    std::vector<float> n(3 * shifted.size());
    hit_normals(scene.tree, RayBatch{shifted.o.data(), shifted.d.data(), 0.0f, nullptr, kInf}, h.t.data(),
                h.prim.data(), n.data(), shifted.size());
    int hits = 0;
    for (size_t i = 0; i < shifted.size(); ++i) {
        ASSERT_EQ(h.prim[i], 0) << "every origin is inside, ray " << i;
        ++hits;
        double len = 0;
        for (int a = 0; a < 3; ++a) {
            const double p = shifted.o[3 * i + a] + double(h.t[i]) * shifted.d[3 * i + a];
            EXPECT_NEAR(n[3 * i + a], (p - balls[0].c[a]) / balls[0].r, 1e-5);
            len += double(n[3 * i + a]) * n[3 * i + a];
        }
        EXPECT_NEAR(len, 1.0, 1e-6);
    }
    EXPECT_EQ(hits, 500);
}

TEST(Spheres, RefusesBadSpheres) {
    SphereSet s;
    const float c[3] = {0, 0, 0}, frame[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, skew[9] = {2, 0, 0, 0, 1, 0, 0, 0, 1};
    const float nan_centre[3] = {0, NAN, 0};
    EXPECT_THROW(s.add(c, 0.0f, frame), std::invalid_argument);
    EXPECT_THROW(s.add(c, -1.0f, frame), std::invalid_argument);
    EXPECT_THROW(s.add(nan_centre, 1.0f, frame), std::invalid_argument);
    EXPECT_THROW(s.add(c, 1.0f, skew), std::invalid_argument);
    EXPECT_TRUE(s.empty());
}

}  // namespace
