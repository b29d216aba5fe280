// K coherent rays through the 8-wide BVH (bvh.h) together, any hit: the lanes over the rays
// (the single-ray traversal, bvh_traverse.h, has them over a node's children). Made for the
// exact direct illuminance's shadow rays (render/lighting/): neighbouring sensors' rays towards
// one luminaire, which enter nearly the same nodes, so each node and leaf block is fetched once
// for the packet instead of once per ray (the kd-tree's packets wait on memory there: its
// deeper tree fetches a node per level).
//
// At a node, each of the eight child boxes is tested against the K rays with hit_children's
// arithmetic per ray lane (test_root_children's form, trace_kernels_bvh_rays.h); the children
// some lane enters go on a stack with those lanes, in slot order (an unblocked ray visits every
// child it enters whatever the order). At a leaf, each triangle is tested against the lanes
// still open by the kd-tree's packet test (intersect_triangle); a lane leaves the packet as soon
// as it is blocked, and the packet ends when every lane is blocked or the stack is empty.
//
// The answer per lane is whether some triangle (or analytic sphere) passes the watertight test
// in (tmin, tmax): the box test is conservative and the triangle test is the kd-tree's, lane by
// lane the same operations, so the result is the kd-tree's and the single-ray BVH's, whatever K
// and whichever lanes share a packet.
#pragma once

#include <limits>

#include "render/accel/bvh.h"
#include "render/accel/bvh_traverse.h"
#include "render/accel/ray_packet.h"
#include "render/accel/sphere_test.h"
#include "render/accel/traverse.h"
#include "render/accel/triangle_test.h"

PATINA_BEGIN_TARGET

namespace bvh_packet_detail {

// What the box test precomputes per ray, in K lanes (load_bvh_rays' arithmetic; the offsets
// negated, which is exact, for the fused multiply-adds).
template <int K>
struct BoxLanes {
    vbool<K> positive[3];  // 1 / d >= +0: the box's low plane is the near one
    vfloat<K> inv[3], minus_near_offset[3], minus_far_offset[3];
    // when every lane agrees on an axis's sign (shadow rays towards one luminaire mostly do):
    // the rows of a node's boxes holding the near and far planes, picked once for the packet
    bool uniform;
    int near_row[3], far_row[3];
};

template <int K>
PATINA_INLINE BoxLanes<K> box_lanes(const Bvh& bvh, const RayPacket<K>& r) {
    using F = vfloat<K>;
    constexpr float kTiny = 0x1p-64f;
    BoxLanes<K> b;
    for (int a = 0; a < 3; ++a) {
        const F d = r.dir[a];
        // components below kTiny in magnitude count as +-kTiny (the sign of d kept): 1 / d is
        // prepare_packet's inv_dir elsewhere, and 1 / +-2^-64 = +-2^64 exactly (no division)
        const F inv = select(abs(d) < F(kTiny), copysign(F(0x1p64f), d), r.inv_dir[a]);
        const F margin = (F(bvh.extent[a]) + abs(r.org[a])) * abs(inv) * F(bvh_detail::kBoxMargin);
        const F scaled_origin = r.org[a] * inv;
        b.inv[a] = inv;
        b.minus_near_offset[a] = -(scaled_origin + margin);
        b.minus_far_offset[a] = -(scaled_origin - margin);
        b.positive[a] = !signbit(inv);
    }
    // the lanes' signs as prepare_packet found them (the sign of d is the sign of 1 / d)
    b.uniform = r.uniform_below_near[0] >= 0 && r.uniform_below_near[1] >= 0 && r.uniform_below_near[2] >= 0;
    for (int a = 0; a < 3; ++a) {
        b.near_row[a] = 2 * a + (r.uniform_below_near[a] == 1 ? 0 : 1);
        b.far_row[a] = 2 * a + (r.uniform_below_near[a] == 1 ? 1 : 0);
    }
    return b;
}

// Lanes of `open` whose ray enters child c's box within [tmin, tmax]: each lane's near and far
// planes picked by its sign, or by the packet's (kUniform: the same planes, so the same bits).
template <int K, bool kUniform>
PATINA_INLINE vbool<K> enters_child(const BvhNode& node, int c, const BoxLanes<K>& b, const RayPacket<K>& r,
                                    vbool<K> open) {
    using F = vfloat<K>;
    F t0 = r.tmin, t1 = r.tmax;
    for (int a = 0; a < 3; ++a) {
        F near_plane, far_plane;
        if constexpr (kUniform) {
            near_plane = F(node.box[b.near_row[a]][c]);
            far_plane = F(node.box[b.far_row[a]][c]);
        } else {
            const F lo(node.box[2 * a][c]), hi(node.box[2 * a + 1][c]);
            near_plane = select(b.positive[a], lo, hi);
            far_plane = select(b.positive[a], hi, lo);
        }
        t0 = max(fmadd(near_plane, b.inv[a], b.minus_near_offset[a]), t0);
        t1 = min(fmadd(far_plane, b.inv[a], b.minus_far_offset[a]), t1);
    }
    return open & (t0 <= t1);
}

// A block's triangle c as intersect_triangle reads it: v0, v1, v2, each x y z.
PATINA_INLINE void block_triangle(const BvhBlock& blk, int c, float* tri) {
    for (int corner = 0; corner < 3; ++corner)
        for (int a = 0; a < 3; ++a) tri[3 * corner + a] = blk.v[corner][a][c];
}

// Lanes of `open` blocked by a triangle of the leaf's blocks.
template <int K>
PATINA_INLINE vbool<K> leaf_blocks(const BvhBlock* blk, uint32_t blocks, const RayPacket<K>& r, vbool<K> open) {
    vbool<K> blocked(false);
    HitPacket<K> unused;  // the any-hit test writes no hit
    for (uint32_t k = 0; k < blocks; ++k, ++blk) {
        for (int c = 0; c < kBvhBlock; ++c) {
            if (c > 0 && blk->prim[c] == blk->prim[c - 1]) continue;  // a block not full repeats its last triangle
            alignas(16) float tri[9];
            block_triangle(*blk, c, tri);
            const vbool<K> got = intersect_triangle<K, true>(r, tri, blk->prim[c], open, unused);
            blocked = blocked | got;
            open = andnot(got, open);
            if (none(open)) return blocked;
        }
    }
    return blocked;
}

// A packet with this many open lanes or fewer at a node goes on as single rays, each with the
// lanes over the node's children (bvh_occluded_triangles): a node then costs one test instead
// of eight, whereas the packet's test costs the same whatever lanes are open. Measured on the
// lighting bench's field at width 8 (shadow part, one thread, medians of 7): 2 lanes 0.083 s,
// 4 0.079, 6 0.077, 8 0.091 (the packet's shared fetches lost); width 16 alike.
template <int K>
constexpr int kSingleRayLanes = 3 * K / 4;

// The lanes of `open` from `node` on, one ray at a time; entered[c]: the lanes entering child c.
template <int K>
PATINA_INLINE vbool<K> single_rays(const Bvh& bvh, const RayPacket<K>& r, const BoxLanes<K>& box, uint32_t node,
                                   const int* entered, vbool<K> open) {
    constexpr int kLanes = K < kBvhWidth ? K : kBvhWidth;
    constexpr int kBlockLanes = K < kBvhBlock ? K : kBvhBlock;
    vbool<K> blocked(false);
    for (int m = movemask(open); m; m &= m - 1) {
        const int j = __builtin_ctz(static_cast<unsigned>(m));
        bvh_detail::RootHits children{0, nullptr, node};  // the any-hit traversal reads no entry distances
        for (int c = 0; c < kBvhWidth; ++c) children.mask |= ((entered[c] >> j) & 1) << c;
        const RayPacket<1> single = traverse_detail::extract_lane<K>(r, j);
        bvh_detail::BoxRay b;
        for (int a = 0; a < 3; ++a) {
            const int positive = lane(box.positive[a], j) ? 1 : 0;
            b.inv[a] = lane(box.inv[a], j);
            b.near_offset[a] = -lane(box.minus_near_offset[a], j);
            b.far_offset[a] = -lane(box.minus_far_offset[a], j);
            b.near_row[a] = 2 * a + 1 - positive;
            b.far_row[a] = 2 * a + positive;
        }
        if (bvh_occluded_triangles<kLanes, kBlockLanes>(bvh, single, b, &children))
            blocked = blocked | traverse_detail::lane_mask<K>(j);
    }
    return blocked;
}

template <int K>
struct StackEntry {
    uint32_t child;
    vbool<K> lanes;  // the lanes that entered its box
};

}  // namespace bvh_packet_detail

// Lanes whose ray hits a triangle in (tmin, tmax), of the lanes not in `done` (lanes with
// tmax < tmin enter nothing and come back clear). r as prepare_packet leaves it.
template <int K>
inline vbool<K> bvh_occluded_triangles_packet(const Bvh& bvh, const RayPacket<K>& r, vbool<K> done) {
    using namespace bvh_packet_detail;
    using B = vbool<K>;
    B blocked(false);
    if (bvh.root == kBvhEmpty) return blocked;
    const BoxLanes<K> box = box_lanes<K>(bvh, r);
    StackEntry<K> stack[bvh_detail::kStackSize];
    int top = 0;
    uint32_t cur = bvh.root;
    B open = andnot(done, B(true));
    for (;;) {
        while (!bvh_is_leaf(cur)) {
            const BvhNode& node = bvh.nodes[cur];
            alignas(64) B enter[kBvhWidth];
            int children = 0;
            for (; children < kBvhWidth && node.child[children] != kBvhEmpty; ++children) {
                enter[children] = box.uniform ? enters_child<K, true>(node, children, box, r, open)
                                              : enters_child<K, false>(node, children, box, r, open);
            }
            if constexpr (K > 1) {
                if (traverse_detail::active_count<K>(open) <= kSingleRayLanes<K>) {
                    int entered[kBvhWidth] = {};
                    for (int c = 0; c < children; ++c) entered[c] = movemask(enter[c]);
                    blocked = blocked | single_rays<K>(bvh, r, box, cur, entered, open);
                    break;
                }
            }
            int first = -1;
            for (int c = 0; c < children; ++c) {
                if (none(enter[c])) continue;
                if (first < 0) {
                    first = c;
                } else {
                    stack[top++] = StackEntry<K>{node.child[c], enter[c]};
                    bvh_detail::prefetch_child(bvh, node.child[c]);
                }
            }
            if (first < 0) break;
            cur = node.child[first];
            open = enter[first];
        }
        if (bvh_is_leaf(cur))
            blocked = blocked | leaf_blocks<K>(&bvh.blocks[bvh_leaf_first(cur)], bvh_leaf_blocks(cur), r, open);
        // the next entry some lane still needs
        for (;;) {
            if (top == 0) return blocked;
            const StackEntry<K>& e = stack[--top];
            open = andnot(blocked, e.lanes);
            if (any(open)) {
                cur = e.child;
                break;
            }
        }
    }
}

// Lanes whose ray hits anything in (tmin, tmax), the analytic spheres (bvh.spheres) included.
template <int K>
PATINA_INLINE vbool<K> bvh_occluded_packet(const Bvh& bvh, const RayPacket<K>& r) {
    const vbool<K> by_sphere =
        bvh.spheres.empty() ? vbool<K>(false) : occluded_by_spheres<K>(bvh.spheres, r.org, r.dir, r.tmin, r.tmax);
    if (all(by_sphere)) return by_sphere;
    return by_sphere | bvh_occluded_triangles_packet<K>(bvh, r, by_sphere);
}

PATINA_END_TARGET
