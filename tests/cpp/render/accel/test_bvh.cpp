// The 8-wide BVH: every width's closest hit is exactly the least (t, primitive) of the
// watertight test over all triangles (so the kd-tree's t, u, v, and the same result at every
// width), against a double-precision brute force too; any hit agrees with closest hit; rays
// along edges and faces, degenerate triangles, an empty scene, one triangle, a thousand
// copies of one triangle (the depth bound).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/cpu.h"
#include "render/accel/bvh.h"
#include "render/accel/bvh_traverse.h"
#include "render/accel/kdtree.h"
#include "render/accel/trace_kernels.h"
#include "render/accel/trace_kernels_bvh_rays.h"
#include "render/accel/triangle_test.h"
#include "tests/cpp/render/accel/trace_test_scenes.h"

using namespace patina;
using namespace trace_test;

namespace {

struct Hits {
    std::vector<float> t, u, v;
    std::vector<int32_t> prim;
    explicit Hits(size_t n) : t(n), u(n), v(n), prim(n) {}
    HitBatch batch() { return HitBatch{t.data(), prim.data(), u.data(), v.data()}; }
};

Bvh build(const KdTree& tree) { return build_bvh(tree.triangles.data(), tree.triangle_count()); }

KdTree kdtree_of(const Mesh& m) {
    return build_kdtree(m.v.data(), m.v.size() / 3, m.f.data(), m.triangles(), KdBuildOptions{});
}

Hits trace(const Bvh& bvh, const Rays& rays, int width, float tmax = kInf) {
    Hits h(rays.size());
    trace_intersect(bvh, RayBatch{rays.o.data(), rays.d.data(), 0.0f, nullptr, tmax}, h.batch(), rays.size(), width,
                    1);
    return h;
}

// The least (t, primitive) of the watertight test (triangle_test.h, one ray) over every triangle.
Hits exhaustive(const KdTree& tree, const Rays& rays, float tmax = kInf) {
    Hits out(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
        RayPacket<1> r;
        for (int a = 0; a < 3; ++a) {
            r.org[a] = rays.o[3 * i + a];
            r.dir[a] = rays.d[3 * i + a];
        }
        r.tmin = 0.0f;
        r.tmax = tmax;
        prepare_packet<1>(r);
        float best = tmax, bu = 0, bv = 0;
        int32_t prim = -1;
        for (size_t p = 0; p < tree.triangle_count(); ++p) {
            HitPacket<1> h{tmax, 0.0f, 0.0f, -1};
            if (!intersect_triangle<1, false>(r, tree.triangles.data() + 9 * p, static_cast<int32_t>(p), true, h))
                continue;
            if (h.t < best || (h.t == best && (prim < 0 || h.prim < prim))) {
                best = h.t;
                bu = h.u;
                bv = h.v;
                prim = h.prim;
            }
        }
        out.t[i] = prim >= 0 ? best : kInf;
        out.u[i] = bu;
        out.v[i] = bv;
        out.prim[i] = prim;
    }
    return out;
}

void expect_identical(const Hits& want, const Hits& got, const char* what, int width) {
    for (size_t i = 0; i < want.t.size(); ++i) {
        ASSERT_EQ(want.prim[i], got.prim[i]) << what << ", width " << width << ", ray " << i;
        ASSERT_EQ(want.t[i], got.t[i]) << what << ", width " << width << ", ray " << i;
        ASSERT_EQ(want.u[i], got.u[i]) << what << ", width " << width << ", ray " << i;
        ASSERT_EQ(want.v[i], got.v[i]) << what << ", width " << width << ", ray " << i;
    }
}

// Every width against the exhaustive test, closest and any hit (tmax from the closest hit's t
// scaled by `tmax_scale`, so about half the rays are blocked).
void expect_exact(const Mesh& m, const Rays& rays, const char* what) {
    const KdTree tree = kdtree_of(m);
    const Bvh bvh = build(tree);
    const Hits want = exhaustive(tree, rays);
    std::vector<float> tmax(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) tmax[i] = want.prim[i] >= 0 ? want.t[i] * (i % 2 ? 1.01f : 0.99f) : 10.0f;
    for (int w : {1, 4, 8, 16}) {
        if (!width_supported(w)) continue;
        expect_identical(want, trace(bvh, rays, w), what, w);
        std::vector<uint8_t> blocked(rays.size());
        trace_occluded(bvh, RayBatch{rays.o.data(), rays.d.data(), 0.0f, tmax.data(), 0.0f}, blocked.data(),
                       rays.size(), w, 1);
        for (size_t i = 0; i < rays.size(); ++i)
            ASSERT_EQ(blocked[i] != 0, want.prim[i] >= 0 && i % 2 == 1) << what << " any hit, width " << w << " ray " << i;
    }
}

// Rays from inside a closed mesh through each of its vertices and edge midpoints.
Rays rays_through_edges(const Mesh& m) {
    const std::array<std::array<float, 3>, 2> origins = {{{0, 0, 0}, {0.1f, -0.2f, 0.05f}}};
    return rays_through_edges(m, origins);
}

// A unit cube of 12 triangles amid clutter, and axis-parallel rays in and along its faces.
void cube_and_axis_rays(Mesh& m, Rays& rays) {
    m.v = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    m.f = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
    const Mesh pile = soup(200, 12);
    const int32_t base = static_cast<int32_t>(m.v.size() / 3);
    m.v.insert(m.v.end(), pile.v.begin(), pile.v.end());
    for (int32_t i : pile.f) m.f.push_back(base + i);
    const float axes[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const auto& d : axes)
        for (float a : {-0.5f, 0.0f, 0.25f, 0.5f, 1.0f})
            for (float b : {0.0f, 0.5f, 0.75f, 1.0f}) {
                rays.add({a, b, 0.5f}, {d[0], d[1], d[2]});
                rays.add({0.5f, a, b}, {d[0], d[1], d[2]});
                rays.add({b, 0.5f, a}, {d[0], d[1], d[2]});
                rays.add({a, b, 0.0f}, {d[0], d[1], d[2]});  // in the plane of a face, along its edges
            }
}

}  // namespace

TEST(Bvh, EveryWidthIsTheExhaustiveWatertightTest) {
    expect_exact(soup(400, 1), random_rays(3000, 2), "soup");
    expect_exact(icosphere(3), random_rays(3000, 3), "icosphere");
    expect_exact(soup(3000, 15), random_rays(1500, 16), "large soup");
    expect_exact(icosphere(4), camera_rays(64, 48), "camera rays");
}

TEST(Bvh, TiesOnSharedEdgesAndVerticesGoToTheLeastPrimitive) {
    const Mesh m = icosphere(3);
    const Rays rays = rays_through_edges(m);
    expect_exact(m, rays, "through edges and vertices");
    const KdTree tree = kdtree_of(m);
    const Hits h = trace(build(tree), rays, 1);
    for (size_t i = 0; i < rays.size(); ++i) ASSERT_GE(h.prim[i], 0) << "ray " << i << " leaked";
}

TEST(Bvh, RaysAlongFacesAndEdges) {
    Mesh m;
    Rays rays;
    cube_and_axis_rays(m, rays);
    expect_exact(m, rays, "axis-parallel rays");
}

TEST(Bvh, MatchesBruteForceInDouble) {
    for (const Mesh& m : {soup(400, 1), icosphere(2)}) {
        const Bvh bvh = build(kdtree_of(m));
        const Rays rays = random_rays(3000, 2);
        const Hits r = trace(bvh, rays, width_supported(8) ? 8 : 1);
        expect_brute_force_hits(m, rays, r.t.data(), r.prim.data(), 300);
    }
}

TEST(Bvh, SameHitsAsTheKdTree) {
    // the same triangle gives the same t, u, v; another one only in a tie
    const Mesh m = icosphere(4);
    const KdTree tree = kdtree_of(m);
    const Bvh bvh = build(tree);
    const Rays rays = random_rays(5000, 4, 0.5f);
    Hits kd(rays.size());
    trace_intersect(tree, RayBatch{rays.o.data(), rays.d.data(), 0.0f, nullptr, kInf}, kd.batch(), rays.size(), 1, 1);
    const Hits h = trace(bvh, rays, 1);
    for (size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(kd.prim[i] >= 0, h.prim[i] >= 0) << "ray " << i;
        if (kd.prim[i] == h.prim[i]) {
            ASSERT_EQ(kd.t[i], h.t[i]) << "ray " << i;
            ASSERT_EQ(kd.u[i], h.u[i]) << "ray " << i;
        } else {
            ASSERT_NEAR(kd.t[i], h.t[i], 1e-6f * h.t[i]) << "ray " << i << ": different primitives, not a tie";
        }
    }
}

TEST(Bvh, DegenerateTrianglesEmptySceneOneTriangle) {
    Mesh m = soup(300, 8);
    const int32_t base = static_cast<int32_t>(m.v.size() / 3);
    m.v.insert(m.v.end(), {0, 0, 0, 1, 1, 1, 0.5f, 0.5f, 0.5f, 0.2f, 0.3f, 0.4f});
    m.f.insert(m.f.end(), {base, base, base + 1, base, base + 1, base + 2, base + 3, base + 3, base + 3});
    expect_exact(m, random_rays(3000, 10), "degenerate triangles");

    const Mesh empty;
    const Bvh none = build(kdtree_of(empty));
    EXPECT_EQ(none.root, kBvhEmpty);
    expect_exact(empty, random_rays(100, 11), "empty scene");

    Mesh one;
    one.v = {-1, -1, 0, 1, -1, 0, 0, 1, 0};
    one.f = {0, 1, 2};
    Rays rays = random_rays(2000, 12);
    rays.add({0, 0, 1}, {0, 0, -1});
    rays.add({0, -1, 1}, {0, 0, -1});  // onto the edge
    rays.add({-1, -1, 1}, {0, 0, -1});  // onto the corner
    expect_exact(one, rays, "one triangle");
    EXPECT_TRUE(bvh_is_leaf(build(kdtree_of(one)).root));
}

TEST(Bvh, CopiesOfOneTriangleStayWithinTheDepthBound) {
    Mesh m;
    m.v = {-1, -1, 0, 1, -1, 0, 0, 1, 0};
    for (int i = 0; i < 3000; ++i) m.f.insert(m.f.end(), {0, 1, 2});
    const KdTree tree = kdtree_of(m);
    const Bvh bvh = build(tree);
    EXPECT_LE(bvh.stats.depth, kBvhMaxDepth);
    // every triangle in some leaf block
    std::vector<int> seen(m.triangles(), 0);
    for (const BvhBlock& b : bvh.blocks)
        for (int32_t p : b.prim) seen[static_cast<size_t>(p)] = 1;
    for (size_t t = 0; t < seen.size(); ++t) ASSERT_EQ(seen[t], 1) << "triangle " << t << " is in no leaf";
    Rays rays = random_rays(300, 13);
    rays.add({0.1f, 0.1f, 2}, {0, 0, -1});
    expect_exact(m, rays, "copies of one triangle");
}

TEST(Bvh, TreeAndHitsDoNotDependOnThreads) {
    const Mesh m = soup(8000, 14);
    const KdTree tree = kdtree_of(m);
    const Bvh a = build(tree), b = build(tree);
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    ASSERT_EQ(a.blocks.size(), b.blocks.size());
    const Rays rays = random_rays(20000, 15);
    Hits one(rays.size()), many(rays.size());
    const RayBatch batch{rays.o.data(), rays.d.data(), 0.0f, nullptr, kInf};
    trace_intersect(a, batch, one.batch(), rays.size(), 0, 1);
    trace_intersect(b, batch, many.batch(), rays.size(), 0, 3);
    expect_identical(one, many, "3 threads", 0);
}

// Small leaves share blocks (the lanes of a block then hold several leaves' triangles): every
// triangle is still in a block, fewer blocks than leaves, and every width's hits stay exact.
TEST(Bvh, SmallLeavesShareBlocks) {
    Mesh m;  // a grid of closed cubes, 12 triangles each: leaves of a few triangles
    const int32_t cube[36] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                              3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
    for (int gx = 0; gx < 12; ++gx)
        for (int gy = 0; gy < 12; ++gy) {
            const int32_t base = static_cast<int32_t>(m.v.size() / 3);
            const float x = -1.2f + 0.2f * gx, y = -1.2f + 0.2f * gy, s = 0.05f + 0.01f * float((gx * 7 + gy) % 5);
            for (int c = 0; c < 8; ++c)
                m.v.insert(m.v.end(), {x + ((c == 1 || c == 2 || c == 5 || c == 6) ? s : 0.0f),
                                       y + ((c == 2 || c == 3 || c == 6 || c == 7) ? s : 0.0f), c >= 4 ? 2 * s : 0.0f});
            for (int32_t i : cube) m.f.push_back(base + i);
        }
    const Bvh bvh = build(kdtree_of(m));
    EXPECT_LT(bvh.stats.blocks, bvh.stats.leaves);
    std::vector<int> seen(m.triangles(), 0);
    for (const BvhBlock& b : bvh.blocks)
        for (int32_t p : b.prim) seen[static_cast<size_t>(p)] = 1;
    for (size_t t = 0; t < seen.size(); ++t) ASSERT_EQ(seen[t], 1) << "triangle " << t << " is in no leaf";
    expect_exact(m, random_rays(4000, 17), "shared blocks");
}

// The kernels set the rays up N at a time (trace_kernels_bvh_rays.h): every width gives the hits
// of one ray at a time through load_ray, also for directions with components that are zero,
// -0 or below 2^-64, for a tmin above 0, per-ray tmax and a batch that ends mid-packet.
TEST(Bvh, RaysSetUpInLanesAreLoadRaysOwn) {
    const Mesh m = soup(3000, 18);
    const Bvh bvh = build(kdtree_of(m));
    Rays rays = random_rays(1000, 19);
    for (float tiny : {0.0f, -0.0f, 1e-30f, -1e-30f, 0x1p-64f, -0x1p-65f})
        for (int a = 0; a < 3; ++a) {
            std::array<float, 3> d = {0.3f, -0.5f, 0.8f};
            d[static_cast<size_t>(a)] = tiny;
            rays.add({0.1f, 0.2f, -2.0f}, d);
            d[static_cast<size_t>((a + 1) % 3)] = -tiny;
            rays.add({-0.3f, 0.1f, 2.0f}, d);
        }
    const size_t n = rays.size() - 5;  // the last packet partial at every width
    std::vector<float> tmax(n);
    for (size_t i = 0; i < n; ++i) tmax[i] = i % 3 ? 4.0f : 1.5f;
    const float tmin = 0.25f;
    Hits want(n);
    std::vector<uint8_t> want_blocked(n);
    for (size_t i = 0; i < n; ++i) {
        HitPacket<1> h;
        bvh_intersect<1, 1>(bvh, &rays.o[3 * i], &rays.d[3 * i], tmin, tmax[i], h);
        want.t[i] = h.prim >= 0 ? h.t : kInf;
        want.u[i] = h.u;
        want.v[i] = h.v;
        want.prim[i] = h.prim;
        want_blocked[i] = bvh_occluded<1, 1>(bvh, &rays.o[3 * i], &rays.d[3 * i], tmin, tmax[i]);
    }
    const RayBatch batch{rays.o.data(), rays.d.data(), tmin, tmax.data(), 0.0f};
    // field by field, in this file's one lane (the hits below check the wide kernels)
    for (size_t i = 0; i < n; ++i) {
        RayPacket<1> want_r, got_r;
        bvh_detail::BoxRay want_b, got_b;
        bvh_detail::load_ray(bvh, &rays.o[3 * i], &rays.d[3 * i], tmin, tmax[i], want_r, want_b);
        BvhRayLanes<1> lanes;
        load_bvh_rays<1>(bvh, batch, i, 1, lanes);
        bvh_ray_of<1>(lanes, 0, tmin, got_r, got_b);
        for (int a = 0; a < 3; ++a) {
            ASSERT_EQ(as_bits(want_b.inv[a]), as_bits(got_b.inv[a])) << "ray " << i;
            ASSERT_EQ(as_bits(want_b.near_offset[a]), as_bits(got_b.near_offset[a])) << "ray " << i;
            ASSERT_EQ(as_bits(want_b.far_offset[a]), as_bits(got_b.far_offset[a])) << "ray " << i;
            ASSERT_EQ(want_b.near_row[a], got_b.near_row[a]) << "ray " << i;
            ASSERT_EQ(want_b.far_row[a], got_b.far_row[a]) << "ray " << i;
        }
        ASSERT_EQ(want_r.kx, got_r.kx);
        ASSERT_EQ(want_r.ky, got_r.ky);
        ASSERT_EQ(want_r.kz, got_r.kz);
        ASSERT_EQ(as_bits(want_r.sx), as_bits(got_r.sx)) << "ray " << i;
        ASSERT_EQ(as_bits(want_r.sy), as_bits(got_r.sy)) << "ray " << i;
        ASSERT_EQ(as_bits(want_r.sz), as_bits(got_r.sz)) << "ray " << i;
        ASSERT_EQ(want_r.tmax, got_r.tmax);
    }
    for (int w : {1, 4, 8, 16}) {
        if (!width_supported(w)) continue;
        Hits got(n);
        trace_intersect(bvh, batch, got.batch(), n, w, 1);
        expect_identical(want, got, "rays set up in lanes", w);
        std::vector<uint8_t> blocked(n);
        trace_occluded(bvh, batch, blocked.data(), n, w, 1);
        for (size_t i = 0; i < n; ++i) ASSERT_EQ(blocked[i], want_blocked[i]) << "any hit, width " << w << " ray " << i;
    }
}
