// Packets of rays through the BVH together, any hit (render/accel/bvh_packet_occlusion.h): at
// widths 4, 8 and 16, lane by lane, the same answer as width 1 and as the kd-tree's occlusion
// query, for coherent shadow rays (a grid of points towards a light, packets that thin out as
// lanes are blocked and go on as single rays), incoherent ones, rays through a closed mesh's
// vertices and edges (the watertight test's ties), analytic spheres in the way, lanes with
// an empty interval, and packets blocked in every lane inside nested shells.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "core/cpu.h"
#include "render/accel/bvh.h"
#include "render/accel/kdtree.h"
#include "render/accel/trace_kernels.h"
#include "tests/cpp/render/accel/trace_test_scenes.h"

using namespace patina;
using namespace trace_test;

namespace {

// A mesh's kd-tree and BVH, with the same analytic spheres.
struct Scene {
    KdTree tree;
    Bvh bvh;
    explicit Scene(const Mesh& m, bool spheres = false)
        : tree(build_kdtree(m.v.data(), m.v.size() / 3, m.f.data(), m.triangles(), KdBuildOptions{})) {
        if (spheres) {
            const float identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
            const float c1[3] = {0.3f, 0.9f, 0.2f}, c2[3] = {-0.6f, 1.2f, -0.4f};
            tree.spheres.add(c1, 0.25f, identity);
            tree.spheres.add(c2, 0.15f, identity);
        }
        bvh = build_bvh(tree.triangles.data(), tree.triangle_count());
        bvh.spheres = tree.spheres;
    }
};

// Shadow rays from a 40 x 40 grid of points below the mesh towards a light above it, in 4 x 4
// tiles (neighbours in a packet), ending just short of the light.
Rays shadow_rays(std::vector<float>& tmax) {
    Rays rays;
    const std::array<float, 3> light{0.2f, 2.5f, -0.1f};
    for (int ty = 0; ty < 40; ty += 4)
        for (int tx = 0; tx < 40; tx += 4)
            for (int y = ty; y < ty + 4; ++y)
                for (int x = tx; x < tx + 4; ++x) {
                    const std::array<float, 3> p{-2.0f + 0.1f * x, -1.5f, -2.0f + 0.1f * y};
                    rays.add(p, {light[0] - p[0], light[1] - p[1], light[2] - p[2]});
                    tmax.push_back(0.9999f);  // the directions run to the light: t in units of |d|
                }
    return rays;
}

// tmax for rays of unit-ish length: far, short, and empty (below tmin) in turn.
std::vector<float> mixed_tmax(size_t n) {
    std::vector<float> tmax(n);
    for (size_t i = 0; i < n; ++i) tmax[i] = i % 5 == 4 ? -1.0f : (i % 3 == 1 ? 0.6f : 10.0f);
    return tmax;
}

// The kd-tree's answer at width 1, and the BVH packets' lane by lane at every width; `mixed`:
// expect a real mix of blocked and clear rays.
void expect_kdtree_answers(const Scene& s, const Rays& rays, const std::vector<float>& tmax, float tmin,
                           const char* what, bool mixed = true) {
    const RayBatch batch{rays.o.data(), rays.d.data(), tmin, tmax.data(), 0.0f};
    std::vector<uint8_t> want(rays.size()), scalar(rays.size()), got(rays.size());
    trace_occluded(s.tree, batch, want.data(), rays.size(), 1, 1);
    trace_occluded_packets(s.bvh, batch, scalar.data(), rays.size(), 1, 1);
    size_t blocked = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(scalar[i], want[i]) << what << ", width 1, ray " << i;
        blocked += want[i];
    }
    if (mixed) {
        EXPECT_GT(blocked, rays.size() / 20) << what;
        EXPECT_LT(blocked, rays.size() - rays.size() / 20) << what;
    }
    for (int w : {4, 8, 16}) {
        if (!width_supported(w)) continue;
        trace_occluded_packets(s.bvh, batch, got.data(), rays.size(), w, 1);
        for (size_t i = 0; i < rays.size(); ++i)
            ASSERT_EQ(got[i], scalar[i]) << what << ", width " << w << " lane " << i % w << " of ray " << i;
    }
}

}  // namespace

TEST(BvhPacketOcclusion, CoherentShadowRaysGiveTheKdTreesAnswerAtEveryWidth) {
    const Scene s(soup(250, 21), true);
    std::vector<float> tmax;
    const Rays rays = shadow_rays(tmax);
    expect_kdtree_answers(s, rays, tmax, 1e-4f, "shadow rays");
}

TEST(BvhPacketOcclusion, IncoherentRaysAndEmptyIntervals) {
    const Scene s(soup(1500, 5), true);
    const Rays rays = random_rays(4000, 9);
    expect_kdtree_answers(s, rays, mixed_tmax(rays.size()), 0.0f, "random rays");
}

TEST(BvhPacketOcclusion, RaysThroughAClosedMeshsVerticesAndEdges) {
    const Mesh m = icosphere(3);
    const Scene s(m);
    const std::array<std::array<float, 3>, 2> origins = {{{0, 0, 0}, {0.1f, -0.2f, 0.05f}}};
    const Rays rays = rays_through_edges(m, origins);
    // the rays reach the mesh at t = 1: blocked when tmax passes it (10), clear when it stops short
    expect_kdtree_answers(s, rays, mixed_tmax(rays.size()), 0.0f, "rays through edges");
}

// Three nested closed icospheres (radii 1, 1.5, 2.5) around the rays' origins: every ray with
// an interval is blocked (the packet ends when its last lane is); every third ray has an empty
// interval (an unlit sensor's lane) and stays clear, so some packets are fully blocked and the
// others blocked in every active lane.
TEST(BvhPacketOcclusion, PacketsBlockedInEveryLaneInsideNestedShells) {
    Mesh shells;
    for (float radius : {1.0f, 1.5f, 2.5f}) {
        const Mesh m = icosphere(3);
        const int32_t base = static_cast<int32_t>(shells.v.size() / 3);
        for (float x : m.v) shells.v.push_back(radius * x);
        for (int32_t i : m.f) shells.f.push_back(base + i);
    }
    const Scene s(shells, true);
    std::vector<float> unused;
    Rays rays = shadow_rays(unused);
    for (float& o : rays.o) o *= 0.2f;  // the grid inside the inner shell, the light outside all three
    std::vector<float> tmax(rays.size()), every(rays.size(), 10.0f);
    for (size_t i = 0; i < rays.size(); ++i) tmax[i] = i % 3 == 2 ? -1.0f : 10.0f;
    expect_kdtree_answers(s, rays, every, 1e-4f, "rays inside shells", false);
    expect_kdtree_answers(s, rays, tmax, 1e-4f, "rays inside shells, every third empty", false);
    const RayBatch batch{rays.o.data(), rays.d.data(), 1e-4f, tmax.data(), 0.0f};
    std::vector<uint8_t> got(rays.size());
    trace_occluded_packets(s.bvh, batch, got.data(), rays.size(), 1, 1);
    for (size_t i = 0; i < rays.size(); ++i) ASSERT_EQ(got[i], i % 3 == 2 ? 0 : 1) << "ray " << i;
}

// Coherent packets where the coordinates are large (the box margins rounded coarsely): the
// grid and mesh moved 1000 along x and 500 along z; lane by lane the width-1 answer and the
// kd-tree's.
TEST(BvhPacketOcclusion, CoherentPacketsFarFromTheOrigin) {
    Mesh m = soup(250, 21);
    const float shift[3] = {1000.0f, 0.0f, 500.0f};
    for (size_t i = 0; i < m.v.size(); ++i) m.v[i] += shift[i % 3];
    const Scene s(m);
    std::vector<float> tmax;
    Rays rays = shadow_rays(tmax);
    for (size_t i = 0; i < rays.o.size(); ++i) rays.o[i] += shift[i % 3];
    expect_kdtree_answers(s, rays, tmax, 1e-4f, "shadow rays far from the origin");
}
