// The kd-tree: single rays against brute force, packets against single rays, a closed
// mesh that must not leak, degenerate input, empty scenes, rays in splitting planes, the
// same tree for any thread count; the ray recorder.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <vector>

#include "core/cpu.h"
#include "render/accel/kdtree.h"
#include "render/accel/ray_recorder.h"
#include "render/accel/trace_kernels.h"
#include "tests/cpp/render/accel/trace_test_scenes.h"

using namespace patina;
using namespace trace_test;

namespace {
KdTree build(const Mesh& m) {
    return build_kdtree(m.v.data(), m.v.size() / 3, m.f.data(), m.triangles(), KdBuildOptions{});
}

struct Result {
    std::vector<float> t, u, v;
    std::vector<int32_t> prim;
};

Result trace(const KdTree& tree, const Rays& rays, int width, float tmax = kInf) {
    Result out;
    const size_t n = rays.size();
    out.t.resize(n);
    out.u.resize(n);
    out.v.resize(n);
    out.prim.resize(n);
    const RayBatch batch{rays.o.data(), rays.d.data(), 0.0f, nullptr, tmax};
    trace_intersect(tree, batch, HitBatch{out.t.data(), out.prim.data(), out.u.data(), out.v.data()}, n, width, 1);
    return out;
}

void expect_same_hits(const Result& a, const Result& b, const char* what) {
    for (size_t i = 0; i < a.t.size(); ++i) {
        ASSERT_EQ(a.t[i] == kInf, b.t[i] == kInf) << what << " ray " << i;
        if (a.prim[i] == b.prim[i]) {
            ASSERT_EQ(a.t[i], b.t[i]) << what << " ray " << i;  // same arithmetic in every lane
            ASSERT_EQ(a.u[i], b.u[i]) << what << " ray " << i;
        } else {
            ASSERT_NEAR(a.t[i], b.t[i], 1e-6f * a.t[i]) << what << " ray " << i << ": different primitives, not a tie";
        }
    }
}
}  // namespace

TEST(KdTree, SingleRaysMatchBruteForce) {
    for (const Mesh& m : {soup(400, 1), icosphere(2)}) {
        const KdTree tree = build(m);
        const Rays rays = random_rays(3000, 2);
        const Result r = trace(tree, rays, 1);
        expect_brute_force_hits(m, rays, r.t.data(), r.prim.data(), 300);
    }
}

TEST(KdTree, PacketsMatchSingleRays) {
    const Mesh sphere = icosphere(4), pile = soup(2000, 3);
    for (const Mesh* m : {&sphere, &pile}) {
        const KdTree tree = build(*m);
        for (const Rays& rays : {camera_rays(64, 48), random_rays(5001, 4)}) {
            const Result single = trace(tree, rays, 1);
            for (int w : {4, 8, 16}) {
                if (width_supported(w)) {
                    const char* what = w == 4 ? "4-ray packets" : w == 8 ? "8-ray packets" : "16-ray packets";
                    expect_same_hits(single, trace(tree, rays, w), what);
                }
            }
        }
    }
}

TEST(KdTree, ClosedMeshNeverLeaks) {
    const Mesh m = icosphere(3);
    const KdTree tree = build(m);
    // from inside, at every vertex, every edge midpoint, and at random
    const std::array<std::array<float, 3>, 3> origins = {{{0, 0, 0}, {0.1f, -0.2f, 0.05f}, {0.5f, 0.3f, -0.2f}}};
    Rays rays = rays_through_edges(m, origins);
    const Rays random = random_rays(20000, 9, 0.3f);
    rays.o.insert(rays.o.end(), random.o.begin(), random.o.end());
    rays.d.insert(rays.d.end(), random.d.begin(), random.d.end());
    for (int w : {1, 4, 8, 16}) {
        if (!width_supported(w)) continue;
        const Result r = trace(tree, rays, w);
        for (size_t i = 0; i < rays.size(); ++i) ASSERT_GE(r.prim[i], 0) << "width " << w << ": ray " << i << " leaked";
        std::vector<uint8_t> blocked(rays.size());
        const RayBatch batch{rays.o.data(), rays.d.data(), 0.0f, nullptr, kInf};
        trace_occluded(tree, batch, blocked.data(), rays.size(), w, 1);
        for (size_t i = 0; i < rays.size(); ++i) ASSERT_EQ(blocked[i], 1) << "width " << w << ": ray " << i << " leaked";
    }
}

TEST(KdTree, OccludedAgreesWithIntersect) {
    const Mesh m = soup(1500, 5);
    const KdTree tree = build(m);
    const Rays rays = random_rays(4003, 6);
    std::vector<float> tmax(rays.size());
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 3.0f);
    for (float& t : tmax) t = u(rng);
    const Result r = trace(tree, rays, 1);
    for (int w : {1, 4, 8, 16}) {
        if (!width_supported(w)) continue;
        std::vector<uint8_t> blocked(rays.size());
        const RayBatch batch{rays.o.data(), rays.d.data(), 0.0f, tmax.data(), 0.0f};
        trace_occluded(tree, batch, blocked.data(), rays.size(), w, 1);
        for (size_t i = 0; i < rays.size(); ++i) ASSERT_EQ(blocked[i] != 0, r.t[i] < tmax[i]) << "width " << w << " ray " << i;
    }
}

TEST(KdTree, DegenerateTrianglesAreHarmless) {
    Mesh m = soup(300, 8);
    const int32_t base = static_cast<int32_t>(m.v.size() / 3);
    // zero area: repeated vertex, collinear points, a point
    m.v.insert(m.v.end(), {0, 0, 0, 1, 1, 1, 0.5f, 0.5f, 0.5f, 0.2f, 0.3f, 0.4f});
    m.f.insert(m.f.end(), {base, base, base + 1, base, base + 1, base + 2, base + 3, base + 3, base + 3});
    const KdTree tree = build(m);
    const Rays rays = random_rays(3000, 10);
    for (int w : {1, 4, 8, 16}) {
        if (!width_supported(w)) continue;
        const Result r = trace(tree, rays, w);
        for (size_t i = 0; i < rays.size(); ++i) {
            EXPECT_LT(r.prim[i], 300) << "hit a zero-area triangle";
            const auto [t, prim] = brute_force(m, &rays.o[3 * i], &rays.d[3 * i]);
            ASSERT_EQ(r.prim[i] >= 0, prim >= 0) << "ray " << i;
        }
    }
}

TEST(KdTree, EmptySceneMissesEverything) {
    const Mesh m;
    const KdTree tree = build(m);
    const Rays rays = random_rays(100, 11);
    for (int w : {1, 4, 8, 16}) {
        if (!width_supported(w)) continue;
        const Result r = trace(tree, rays, w);
        for (size_t i = 0; i < rays.size(); ++i) {
            EXPECT_EQ(r.prim[i], -1);
            EXPECT_EQ(r.t[i], kInf);
        }
    }
}

TEST(KdTree, RaysInAndAlongSplittingPlanes) {
    // a unit cube of 12 triangles, its planes become the tree's splitting planes
    Mesh m;
    m.v = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    m.f = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
    const Mesh pile = soup(200, 12);  // and clutter around it, so the tree has depth
    const int32_t base = static_cast<int32_t>(m.v.size() / 3);
    m.v.insert(m.v.end(), pile.v.begin(), pile.v.end());
    for (int32_t i : pile.f) m.f.push_back(base + i);
    const KdTree tree = build(m);
    Rays rays;
    const float axes[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const auto& d : axes)
        for (float a : {0.0f, 0.25f, 0.5f, 1.0f})
            for (float b : {0.0f, 0.5f, 0.75f, 1.0f}) {
                rays.add({a, b, 0.5f}, {d[0], d[1], d[2]});
                rays.add({0.5f, a, b}, {d[0], d[1], d[2]});
                rays.add({b, 0.5f, a}, {d[0], d[1], d[2]});
            }
    const Result single = trace(tree, rays, 1);
    for (size_t i = 0; i < rays.size(); ++i) {
        const auto [t, prim] = brute_force(m, &rays.o[3 * i], &rays.d[3 * i]);
        if (prim >= 0 && single.prim[i] >= 0) {
            EXPECT_NEAR(single.t[i], t, 1e-5 * t + 1e-6) << "ray " << i;
        }
    }
    for (int w : {4, 8, 16}) {
        if (width_supported(w)) expect_same_hits(single, trace(tree, rays, w), "axis-parallel rays");
    }
}

TEST(KdTree, EveryTriangleIsInALeafAndLimitsHold) {
    const Mesh m = soup(5000, 13);
    KdBuildOptions opt;
    opt.max_depth = 12;
    const KdTree tree = build_kdtree(m.v.data(), m.v.size() / 3, m.f.data(), m.triangles(), opt);
    EXPECT_LE(tree.stats.depth, 12);
    std::vector<int> seen(m.triangles(), 0);
    for (const KdNode& n : tree.nodes)
        if (n.is_leaf())
            for (uint32_t i = 0; i < n.count(); ++i) seen[tree.leaf_prims[n.first + i]] = 1;
    for (size_t t = 0; t < seen.size(); ++t) ASSERT_EQ(seen[t], 1) << "triangle " << t << " is in no leaf";
    EXPECT_GT(tree.stats.leaves, 100u);
}


TEST(KdTree, SameTreeForAnyThreadCount) {
    // large enough that the top levels are built in parallel subtrees (and binned)
    const Mesh m = soup(8000, 14);
    KdBuildOptions opt;
    opt.threads = 1;
    const KdTree one = build_kdtree(m.v.data(), m.v.size() / 3, m.f.data(), m.triangles(), opt);
    for (int threads : {2, 3, 8}) {
        opt.threads = threads;
        const KdTree many = build_kdtree(m.v.data(), m.v.size() / 3, m.f.data(), m.triangles(), opt);
        ASSERT_EQ(one.nodes.size(), many.nodes.size()) << threads << " threads";
        for (size_t i = 0; i < one.nodes.size(); ++i) {
            ASSERT_EQ(one.nodes[i].bits, many.nodes[i].bits) << threads << " threads, node " << i;
            ASSERT_EQ(one.nodes[i].first, many.nodes[i].first) << threads << " threads, node " << i;
        }
        ASSERT_EQ(one.leaf_prims, many.leaf_prims) << threads << " threads";
    }
}

TEST(KdTree, LargeSoupMatchesBruteForce) {
    // thousands of overlapping triangles: the binned upper levels, the sorted events below
    // and many triangles clipped to both sides of a plane
    const Mesh m = soup(3000, 15);
    const KdTree tree = build(m);
    EXPECT_GT(tree.stats.leaf_refs, m.triangles()) << "no triangle was clipped into two leaves";
    const Rays rays = random_rays(1500, 16);
    for (int w : {1, 8}) {
        if (!width_supported(w)) continue;
        const Result r = trace(tree, rays, w);
        for (size_t i = 0; i < rays.size(); ++i) {
            const auto [t, prim] = brute_force(m, &rays.o[3 * i], &rays.d[3 * i]);
            ASSERT_EQ(r.prim[i] >= 0, prim >= 0) << "width " << w << " ray " << i;
            if (prim >= 0) {
                // relative, plus float rounding at the origins' scale (1) for hits very near them
                EXPECT_NEAR(r.t[i], t, 1e-5 * t + 1e-6) << "width " << w << " ray " << i;
            }
        }
    }
}

TEST(RayRecorder, KeepsWhatTheKernelsTraceWhileOn) {
    const Mesh m = soup(200, 17);
    const KdTree tree = build(m);
    const Rays rays = random_rays(100, 18);
    trace(tree, rays, 1);  // not recorded: recording is off
    start_ray_recording(150);
    trace(tree, rays, 1);
    std::vector<uint8_t> blocked(rays.size());
    const RayBatch batch{rays.o.data(), rays.d.data(), 0.0f, nullptr, 2.0f};
    trace_occluded(tree, batch, blocked.data(), rays.size(), 1, 1);
    const RecordedRays rec = stop_ray_recording();
    trace(tree, rays, 1);  // off again
    ASSERT_EQ(rec.tmax.size(), 150u);
    EXPECT_TRUE(rec.truncated);
    ASSERT_EQ(rec.origins.size(), 450u);
    for (size_t i = 0; i < 150; ++i) {
        const size_t k = i % 100;
        for (int a = 0; a < 3; ++a) {
            ASSERT_EQ(rec.origins[3 * i + a], rays.o[3 * k + a]) << "ray " << i;
            ASSERT_EQ(rec.directions[3 * i + a], rays.d[3 * k + a]) << "ray " << i;
        }
        EXPECT_EQ(rec.any_hit[i], i < 100 ? 0 : 1) << "ray " << i;
        EXPECT_EQ(rec.tmax[i], i < 100 ? kInf : 2.0f) << "ray " << i;
        EXPECT_EQ(rec.tmin[i], 0.0f);
    }
    EXPECT_TRUE(stop_ray_recording().tmax.empty());
}
