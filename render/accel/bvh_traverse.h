// One ray through the 8-wide BVH (bvh.h), the SIMD lanes over a node's children: L lanes
// (8, 4 or 1) test the eight child boxes, the children hit are visited nearest first (the
// others wait on a small stack with their entry distances), and a leaf's blocks are tested
// T triangles (8, 4 or 1) at a time with the kd-tree's watertight arithmetic.
//
// Every width gives the same result: the triangle test is the same operations per triangle
// lane as per ray lane in the kd-tree's packets (so the same t, u, v as the kd-tree), the
// closest hit is the least (t, primitive index) over all triangles the test accepts (so ties
// and the visiting order do not matter), and the box test is conservative (below).
//
// Box test: the slab distances are box * (1/d) - origin * (1/d), widened on each plane by a
// margin of 32 float ulps of (|coordinate| + |origin|) |1/d|, with the geometry's largest
// coordinate for |coordinate|: more than the rounding of the distances, fused or not, and
// of the watertight test's shear. A box the ray grazes is thus entered, and the triangle
// test decides. Direction components below 2^-64 in magnitude count as +-2^-64 there
// (as Embree does): no 0 * inf, and a ray lying in a box's face keeps the whole slab.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "render/accel/bvh.h"
#include "render/accel/sphere_test.h"
#include "render/accel/triangle_test.h"

PATINA_BEGIN_TARGET

namespace bvh_detail {
constexpr float kBoxMargin = 32.0f / (1 << 23);
constexpr int kStackSize = (kBvhWidth - 1) * kBvhMaxDepth + 1;

// What the box test precomputes per ray.
struct BoxRay {
    float inv[3];
    // near plane distance = box[near_row[a]] * inv[a] - near_offset[a]; far likewise
    float near_offset[3], far_offset[3];
    int near_row[3], far_row[3];
};

// Ray i of the batch for the triangle test (the fields intersect_triangle reads, with
// prepare_packet's arithmetic) and for the box test.
PATINA_INLINE void load_ray(const Bvh& bvh, const float* org, const float* dir, float tmin, float tmax,
                            RayPacket<1>& r, BoxRay& b) {
    constexpr float kTiny = 0x1p-64f;
    for (int a = 0; a < 3; ++a) {
        r.org[a] = org[a];
        r.dir[a] = dir[a];
        const float d = dir[a];
        const float inv = std::fabs(d) < kTiny ? 1.0f / std::copysign(kTiny, d) : 1.0f / d;
        const float margin = (bvh.extent[a] + std::fabs(org[a])) * std::fabs(inv) * kBoxMargin;
        const float o = org[a] * inv;
        const bool positive = !std::signbit(inv);
        b.inv[a] = inv;
        b.near_offset[a] = o + margin;
        b.far_offset[a] = o - margin;
        b.near_row[a] = 2 * a + (positive ? 0 : 1);
        b.far_row[a] = 2 * a + (positive ? 1 : 0);
    }
    r.tmin = tmin;
    r.tmax = tmax;
    const float ax = std::fabs(dir[0]), ay = std::fabs(dir[1]), az = std::fabs(dir[2]);
    const int kz = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    if (dir[kz] < 0.0f) std::swap(kx, ky);
    r.kx = r.ukx = kx;
    r.ky = r.uky = ky;
    r.kz = r.ukz = kz;
    r.uniform_axes = true;
    r.sz = b.inv[kz];  // 1 / dir[kz]: the largest component is never below kTiny
    r.sx = dir[kx] * r.sz;
    r.sy = dir[ky] * r.sz;
}

// Bit i set where the ray enters child i within [tmin, tmax]; entry distances into `near`
// (kNear: the any-hit traversal needs none).
template <int L, bool kNear = true>
PATINA_INLINE int hit_children(const BvhNode& node, const BoxRay& b, float tmin, float tmax, float* near) {
    using F = vfloat<L>;
    int mask = 0;
    for (int c = 0; c < kBvhWidth; c += L) {
        F t0(tmin), t1(tmax);
        for (int a = 0; a < 3; ++a) {
            const F inv(b.inv[a]);
            const F n = fmadd(load_n<L>(&node.box[b.near_row[a]][c]), inv, F(-b.near_offset[a]));
            const F f = fmadd(load_n<L>(&node.box[b.far_row[a]][c]), inv, F(-b.far_offset[a]));
            t0 = max(n, t0);
            t1 = min(f, t1);
        }
        if constexpr (kNear) store_n<L>(near + c, t0);
        mask |= movemask(t0 <= t1) << c;
    }
    return mask;
}

// The triangles [c, c + T) of a block against the ray: sheared vertices, edge functions and
// the distance test exactly as intersect_triangle does them for a ray lane. Closest hit: the
// lanes hit in (tmin, tmax] no farther than `best`, with their t, u, v; any hit: the lanes hit
// in (tmin, tmax).
template <int T, bool kAnyHit>
PATINA_INLINE vbool<T> block_lanes(const RayPacket<1>& r, const BvhBlock& blk, int c, float best, vfloat<T>& t,
                                   vfloat<T>& u, vfloat<T>& v) {
    using F = vfloat<T>;
    F x[3], y[3], z[3];
    for (int k = 0; k < 3; ++k) {
        z[k] = load_n<T>(&blk.v[k][r.ukz][c]) - F(r.org[r.ukz]);
        x[k] = (load_n<T>(&blk.v[k][r.ukx][c]) - F(r.org[r.ukx])) - F(r.sx) * z[k];
        y[k] = (load_n<T>(&blk.v[k][r.uky][c]) - F(r.org[r.uky])) - F(r.sy) * z[k];
    }
    const F ax = x[0], ay = y[0], bx = x[1], by = y[1], cx = x[2], cy = y[2];
    F eu = cx * by - cy * bx;
    F ev = ax * cy - ay * cx;
    F ew = bx * ay - by * ax;
    if (any((eu == F(0.0f)) | (ev == F(0.0f)) | (ew == F(0.0f))))
        tri_detail::refine_in_double<T>(eu, ev, ew, ax, ay, bx, by, cx, cy);
    const vbool<T> negative = (eu < F(0.0f)) | (ev < F(0.0f)) | (ew < F(0.0f));
    const vbool<T> positive = (eu > F(0.0f)) | (ev > F(0.0f)) | (ew > F(0.0f));
    const F det = eu + ev + ew;
    vbool<T> valid = andnot(negative & positive, det != F(0.0f));
    if (none(valid)) return valid;
    const F t_scaled = (eu * z[0] + ev * z[1] + ew * z[2]) * F(r.sz);
    const F signed_t = xorsign(t_scaled, det);
    const F abs_det = abs(det);
    valid = valid & (signed_t > F(r.tmin) * abs_det);
    valid = valid & (kAnyHit ? (signed_t < F(r.tmax) * abs_det) : (signed_t <= F(r.tmax) * abs_det));
    if (kAnyHit || none(valid)) return valid;
    const F inv_det = F(1.0f) / det;
    t = t_scaled * inv_det;
    u = ev * inv_det;
    v = ew * inv_det;
    return valid & (t <= F(best));
}

// The root node's children a ray enters (bit c: child c) and their entry distances, as
// hit_children gives them, when found before the traversal.
struct RootHits {
    int mask;
    const float* near;  // kBvhWidth entry distances (read where mask has a bit)
    // the node whose children these are: the root (node 0), or where a packet traversal
    // (bvh_packet_occlusion.h) hands a ray over to continue alone
    uint32_t node = 0;
};

struct StackEntry {
    uint32_t child;
    float tnear;
};

// A child waiting on the stack is fetched from memory meanwhile.
PATINA_INLINE void prefetch_child(const Bvh& bvh, uint32_t child) {
    const char* p = bvh_is_leaf(child) ? reinterpret_cast<const char*>(&bvh.blocks[bvh_leaf_first(child)])
                                       : reinterpret_cast<const char*>(&bvh.nodes[child]);
    for (size_t line = 0; line < sizeof(BvhNode); line += 64) __builtin_prefetch(p + line);
}

// The children hit (mask) onto the stack, farthest first; returns the nearest. Up to three
// children hit (all but 4 % of the node tests of the box field's bounce rays) are ordered by
// compare-and-swap, without the insertion sort's loops and their mispredicted branches.
PATINA_INLINE uint32_t order_children(const Bvh& bvh, const BvhNode& node, int mask, const float* near, StackEntry* stack,
                                      int& top) {
    const int first = __builtin_ctz(static_cast<unsigned>(mask));
    mask &= mask - 1;
    if (mask == 0) return node.child[first];
    const int second = __builtin_ctz(static_cast<unsigned>(mask));
    const int rest = mask & (mask - 1);
    if ((rest & (rest - 1)) == 0) {
        StackEntry a{node.child[first], near[first]}, b{node.child[second], near[second]};
        if (a.tnear < b.tnear) std::swap(a, b);
        if (rest != 0) {
            const int third = __builtin_ctz(static_cast<unsigned>(rest));
            StackEntry c{node.child[third], near[third]};
            if (b.tnear < c.tnear) std::swap(b, c);
            if (a.tnear < b.tnear) std::swap(a, b);
            stack[top++] = a;
            prefetch_child(bvh, a.child);
            a = b;
            b = c;
        }
        stack[top++] = a;
        prefetch_child(bvh, a.child);
        return b.child;
    }
    // few children are hit: insertion-sort them by entry distance, nearest last
    StackEntry hit[kBvhWidth];
    int n = 0;
    hit[n++] = StackEntry{node.child[first], near[first]};
    for (; mask; mask &= mask - 1) {
        const int i = __builtin_ctz(static_cast<unsigned>(mask));
        StackEntry e{node.child[i], near[i]};
        int j = n++;
        while (j > 0 && hit[j - 1].tnear < e.tnear) {
            hit[j] = hit[j - 1];
            --j;
        }
        hit[j] = e;
    }
    for (int j = 0; j < n - 1; ++j) {
        stack[top++] = hit[j];
        prefetch_child(bvh, hit[j].child);
    }
    return hit[n - 1].child;
}

// The children hit (mask) onto the stack in slot order, unsorted; returns the first. For any
// hit: a ray that is not blocked visits every child it enters whatever the order, so sorting
// them by distance would be work for nothing on most shadow rays.
PATINA_INLINE uint32_t push_children(const Bvh& bvh, const BvhNode& node, int mask, StackEntry* stack, int& top) {
    const int first = __builtin_ctz(static_cast<unsigned>(mask));
    for (mask &= mask - 1; mask; mask &= mask - 1) {
        const int i = __builtin_ctz(static_cast<unsigned>(mask));
        stack[top++].child = node.child[i];  // tnear unused: the any-hit pop does not test it
        prefetch_child(bvh, node.child[i]);
    }
    return node.child[first];
}

// The traversal both queries share: nodes with L lanes over their children, nearest child first
// (kNearestFirst; else in slot order), the others on the stack; nearest first, a popped child is
// skipped once it lies beyond `tfar` (the closest hit so far, which the leaf visitor may lower).
// `leaf(first_block, block_count)` returns true to stop. With a `root` given, the children of
// its node were tested already (RootHits: for N rays at once, trace_kernels_bvh_rays.h), and
// the traversal goes on from there.
template <int L, bool kNearestFirst, typename Leaf>
inline void traverse(const Bvh& bvh, const RayPacket<1>& r, const BoxRay& b, const float& tfar, Leaf&& leaf,
                     const RootHits* root = nullptr) {
    StackEntry stack[kStackSize];
    int top = 0;
    uint32_t cur = bvh.root;
    alignas(32) float near[kBvhWidth];
    if (root != nullptr) {
        if (root->mask == 0) return;
        const BvhNode& node = bvh.nodes[root->node];
        cur = kNearestFirst ? order_children(bvh, node, root->mask, root->near, stack, top)
                            : push_children(bvh, node, root->mask, stack, top);
    }
    for (;;) {
        while (!bvh_is_leaf(cur)) {
            const BvhNode& node = bvh.nodes[cur];
            const int mask = hit_children<L, kNearestFirst>(node, b, r.tmin, tfar, near);
            if (mask == 0) goto pop;
            cur = kNearestFirst ? order_children(bvh, node, mask, near, stack, top)
                                : push_children(bvh, node, mask, stack, top);
        }
        if (leaf(&bvh.blocks[bvh_leaf_first(cur)], bvh_leaf_blocks(cur))) return;
    pop:
        for (;;) {
            if (top == 0) return;
            const StackEntry& e = stack[--top];
            // Any hit: tfar stays r.tmax and a child is pushed only when entered by then, so the
            // test would always pass; skipping it leaves the entry distances dead (not stored).
            if (!kNearestFirst || e.tnear <= tfar) {
                cur = e.child;
                break;
            }
        }
    }
}
}  // namespace bvh_detail

// The triangles' closest hit, from `hit`: a miss (prim -1, t = r.tmax) or the analytic
// spheres' hit, which the triangles' traversal then only searches in front of.
// `root`: the root node's children tested already (an interior root only).
template <int L, int T>
inline void bvh_intersect_triangles(const Bvh& bvh, const RayPacket<1>& r, const bvh_detail::BoxRay& b,
                                    HitPacket<1>& hit, const bvh_detail::RootHits* root = nullptr) {
    using namespace bvh_detail;
    if (bvh.root == kBvhEmpty) return;
    traverse<L, true>(bvh, r, b, hit.t, [&](const BvhBlock* blk, uint32_t nb) {
        for (uint32_t k = 0; k < nb; ++k, ++blk) {
            for (int c = 0; c < kBvhBlock; c += T) {
                vfloat<T> t(0.0f), u(0.0f), v(0.0f);
                const int valid = movemask(block_lanes<T, false>(r, *blk, c, hit.t, t, u, v));
                for (int m = valid; m; m &= m - 1) {
                    const int j = __builtin_ctz(static_cast<unsigned>(m));
                    const float tj = lane(t, j);
                    const int32_t pj = blk->prim[c + j];
                    if (tj < hit.t || (tj == hit.t && (hit.prim < 0 || pj < hit.prim))) {
                        hit.t = tj;
                        hit.u = lane(u, j);
                        hit.v = lane(v, j);
                        hit.prim = pj;
                    }
                }
            }
        }
        return false;
    }, root);
}

// Closest hit (the least t, then the least primitive index) of the ray in (tmin, tmax], with L lanes over the
// children and T over a block's triangles, the analytic spheres (bvh.spheres) included.
// hit.prim = -1 and hit.t = r.tmax on a miss. The ray as load_ray prepares it (r, b:
// trace_kernels_bvh_rays.h prepares N at a time, and tests their spheres N at a time).
template <int L, int T>
inline void bvh_intersect(const Bvh& bvh, const RayPacket<1>& r, const bvh_detail::BoxRay& b, HitPacket<1>& hit) {
    hit.t = r.tmax;
    hit.u = hit.v = 0.0f;
    hit.prim = -1;
    if (!bvh.spheres.empty()) intersect_spheres<1>(bvh.spheres, r.org, r.dir, r.tmin, hit.t, hit.prim);
    bvh_intersect_triangles<L, T>(bvh, r, b, hit);
}

template <int L, int T>
inline void bvh_intersect(const Bvh& bvh, const float* org, const float* dir, float tmin, float tmax,
                          HitPacket<1>& hit) {
    RayPacket<1> r;
    bvh_detail::BoxRay b;
    bvh_detail::load_ray(bvh, org, dir, tmin, tmax, r, b);
    bvh_intersect<L, T>(bvh, r, b, hit);
}

// Whether the ray hits a triangle in (tmin, tmax).
template <int L, int T>
inline bool bvh_occluded_triangles(const Bvh& bvh, const RayPacket<1>& r, const bvh_detail::BoxRay& b,
                                   const bvh_detail::RootHits* root = nullptr) {
    using namespace bvh_detail;
    if (bvh.root == kBvhEmpty) return false;
    bool occluded = false;
    traverse<L, false>(bvh, r, b, r.tmax, [&](const BvhBlock* blk, uint32_t nb) {
        for (uint32_t k = 0; k < nb; ++k, ++blk) {
            for (int c = 0; c < kBvhBlock; c += T) {
                vfloat<T> t(0.0f), u(0.0f), v(0.0f);
                if (any(block_lanes<T, true>(r, *blk, c, r.tmax, t, u, v))) return occluded = true;
            }
        }
        return false;
    }, root);
    return occluded;
}

// Whether the ray hits anything in (tmin, tmax), the analytic spheres included.
template <int L, int T>
inline bool bvh_occluded(const Bvh& bvh, const RayPacket<1>& r, const bvh_detail::BoxRay& b) {
    if (!bvh.spheres.empty() && occluded_by_spheres<1>(bvh.spheres, r.org, r.dir, r.tmin, r.tmax)) return true;
    return bvh_occluded_triangles<L, T>(bvh, r, b);
}

template <int L, int T>
inline bool bvh_occluded(const Bvh& bvh, const float* org, const float* dir, float tmin, float tmax) {
    RayPacket<1> r;
    bvh_detail::BoxRay b;
    bvh_detail::load_ray(bvh, org, dir, tmin, tmax, r, b);
    return bvh_occluded<L, T>(bvh, r, b);
}

PATINA_END_TARGET
