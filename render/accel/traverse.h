// kd-tree traversal for K rays at once, written once for K = 1 (single rays), 4 and 8
// (thesis, ch. 1: four-ray tracing). A packet walks the tree together with an
// active-lane mask. At an interior node each lane classifies the children (near only,
// far only, both); when all lanes agree one child is visited, otherwise both are,
// each with the lanes that need it (the other lanes masked off), nearer child first
// for most lanes. A packet reduced to one active lane continues as a single ray.
//
// Robustness: (plane - origin) / direction is rounded, and perfect splits make cells
// far thinner than that rounding near shared vertices, so each plane distance is
// widened by a margin proportional to its operands' magnitudes. Cells are then
// entered conservatively (a ray through a vertex on a cell corner visits the cell);
// the triangle test, not the cell interval, decides the hits.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "render/accel/kdtree.h"
#include "render/accel/sphere_test.h"
#include "render/accel/triangle_test.h"

PATINA_BEGIN_TARGET

struct TreeView {
    const KdNode* nodes;
    const uint32_t* leaf_prims;
    const float* triangles;
    Box3 bounds;
    const SphereSet* spheres;  // tested before the tree: their hits bound its traversal
};

inline TreeView tree_view(const KdTree& tree) {
    return TreeView{tree.nodes.empty() ? nullptr : tree.nodes.data(), tree.leaf_prims.data(), tree.triangles.data(),
                    tree.bounds, &tree.spheres};
}

namespace traverse_detail {
constexpr int kStackSize = 128;
// A packet with this many active lanes or fewer continues as single rays (measured: 2 of 8
// already costs more as single rays than as a packet).
template <int K>
constexpr int kSingleRayLanes = 1;

// Distance along the rays to the plane x[a] = p, and its rounding margin
// ((|p| + |origin|) |1/d| kPlaneMargin, with the origin's part precomputed).
template <int K>
PATINA_INLINE vfloat<K> plane_distance(const RayPacket<K>& r, int a, float p, vfloat<K>& margin) {
    margin = madd(vfloat<K>(std::fabs(p)), r.margin_per_unit[a], r.margin_of_origin[a]);
    return (vfloat<K>(p) - r.org[a]) * r.inv_dir[a];
}

template <int K>
struct Entry {
    uint32_t node;
    vfloat<K> tmin, tmax;  // lanes that do not visit the node have tmin > tmax
};

// Clips the rays to the scene box (slab test); lanes that miss it get tmin > tmax.
template <int K>
PATINA_INLINE void clip_to_box(const RayPacket<K>& r, const Box3& b, vfloat<K>& t0, vfloat<K>& t1) {
    using F = vfloat<K>;
    t0 = r.tmin;
    t1 = r.tmax;
    for (int a = 0; a < 3; ++a) {
        F mlo, mhi;
        const F lo = plane_distance<K>(r, a, b.lo[a], mlo);
        const F hi = plane_distance<K>(r, a, b.hi[a], mhi);
        const F margin = max(mlo, mhi);
        // min/max pick the non-NaN operand second, so a ray in the slab plane keeps its interval
        t0 = max(min(lo, hi) - margin, t0);
        t1 = min(max(lo, hi) + margin, t1);
    }
}

template <int K>
PATINA_INLINE int active_count(vbool<K> m) {
    if constexpr (K == 1) return m ? 1 : 0;
    else return __builtin_popcount(static_cast<unsigned>(movemask(m)));
}

// The mask with only lane j set.
template <int K>
PATINA_INLINE vbool<K> lane_mask(int j) {
    alignas(32) int32_t m[K] = {};
    m[j] = 1;
    return vint<K>::load(m) == vint<K>(1);
}

template <int K>
PATINA_INLINE RayPacket<1> extract_lane(const RayPacket<K>& r, int j) {
    RayPacket<1> s;
    for (int a = 0; a < 3; ++a) {
        s.org[a] = lane(r.org[a], j);
        s.dir[a] = lane(r.dir[a], j);
        s.inv_dir[a] = lane(r.inv_dir[a], j);
        s.margin_per_unit[a] = lane(r.margin_per_unit[a], j);
        s.margin_of_origin[a] = lane(r.margin_of_origin[a], j);
        s.below_near[a] = lane(r.below_near[a], j);
        s.uniform_below_near[a] = s.below_near[a] ? 1 : 0;
    }
    s.tmin = lane(r.tmin, j);
    s.tmax = lane(r.tmax, j);
    s.kx = lane(r.kx, j);
    s.ky = lane(r.ky, j);
    s.kz = lane(r.kz, j);
    s.sx = lane(r.sx, j);
    s.sy = lane(r.sy, j);
    s.sz = lane(r.sz, j);
    s.uniform_axes = true;
    s.ukx = s.kx;
    s.uky = s.ky;
    s.ukz = s.kz;
    return s;
}
}  // namespace traverse_detail

// Walks the subtree at `root` for the lanes whose [t0, t1] is not empty. Closest hit:
// updates `hit` (hit.t starts at the rays' tmax). Any hit (kAnyHit): returns the lanes
// that hit something in (tmin, tmax) and stops as soon as all active lanes have.
template <int K, bool kAnyHit>
inline vbool<K> traverse_from(const TreeView& tree, const RayPacket<K>& r, uint32_t root, vfloat<K> t0, vfloat<K> t1,
                              HitPacket<K>& hit) {
    using F = vfloat<K>;
    using B = vbool<K>;
    using namespace traverse_detail;
    const F inf(std::numeric_limits<float>::infinity());
    Entry<K> stack[kStackSize];
    int top = 0;
    B occluded(false);
    uint32_t index = root;
    for (;;) {
        B active = (t0 <= t1) & (t0 <= hit.t);
        if (kAnyHit) active = andnot(occluded, active);
        if constexpr (K > 1) {
            if (active_count<K>(active) <= kSingleRayLanes<K>) {
                // few lanes left: each continues alone, with the scalar path's arithmetic
                for (int m = movemask(active); m; m &= m - 1) {
                    const int j = __builtin_ctz(static_cast<unsigned>(m));
                    const RayPacket<1> single = extract_lane<K>(r, j);
                    HitPacket<1> h{lane(hit.t, j), lane(hit.u, j), lane(hit.v, j), lane(hit.prim, j)};
                    const bool blocked = traverse_from<1, kAnyHit>(tree, single, index, lane(t0, j), lane(t1, j), h);
                    const B here = lane_mask<K>(j);
                    if (kAnyHit) {
                        if (blocked) occluded = occluded | here;
                    } else {
                        hit.t = select(here, F(h.t), hit.t);
                        hit.u = select(here, F(h.u), hit.u);
                        hit.v = select(here, F(h.v), hit.v);
                        hit.prim = select(here, vint<K>(h.prim), hit.prim);
                    }
                }
                active = B(false);
            }
        }
        if (any(active)) {
            const KdNode* node = &tree.nodes[index];
            while (!node->is_leaf()) {
                const int a = node->axis();
                F margin;
                const F ts = plane_distance<K>(r, a, node->split, margin);
                const F ts_lo = ts - margin, ts_hi = ts + margin;
                // Near is the child the ray direction enters first; the ray crosses into the
                // far child at ts, known within [ts_lo, ts_hi]. Each child gets every t it
                // might cover. A NaN ts (a ray lying in the plane) keeps the whole interval
                // on both sides: the comparisons fail and min/max return their second operand.
                const B need_near = andnot(ts_hi < t0, active);
                const B need_far = andnot(ts_lo > t1, active);
                const F near_t1 = min(ts_hi, t1);
                const F far_t0 = max(ts_lo, t0);
                const uint32_t below = static_cast<uint32_t>(node - tree.nodes) + 1;
                const uint32_t above = node->above();
                const int uniform = r.uniform_below_near[a];
                if (uniform >= 0) {
                    // all lanes agree on the order of the children
                    const uint32_t near_child = uniform ? below : above, far_child = uniform ? above : below;
                    if (none(need_far)) {
                        index = near_child;
                        t1 = near_t1;
                    } else if (none(need_near)) {
                        index = far_child;
                        t0 = select(need_far, far_t0, inf);
                    } else {
                        if (top < kStackSize) stack[top++] = Entry<K>{far_child, select(need_far, far_t0, inf), t1};
                        index = near_child;
                        t0 = select(need_near, t0, inf);
                        t1 = near_t1;
                        active = need_near;
                    }
                } else {
                    // the lanes disagree: both children, each with the lanes that need it,
                    // first the one that is near for most of the active lanes
                    const B below_near = r.below_near[a];
                    const B need_below = select(below_near, need_near, need_far);
                    const B need_above = select(below_near, need_far, need_near);
                    const F below_t0 = select(need_below, select(below_near, t0, far_t0), inf);
                    const F below_t1 = select(below_near, near_t1, t1);
                    const F above_t0 = select(need_above, select(below_near, far_t0, t0), inf);
                    const F above_t1 = select(below_near, t1, near_t1);
                    if (none(need_above)) {
                        index = below;
                        t0 = below_t0;
                        t1 = below_t1;
                        active = need_below;
                    } else if (none(need_below)) {
                        index = above;
                        t0 = above_t0;
                        t1 = above_t1;
                        active = need_above;
                    } else {
                        const bool below_first = 2 * active_count<K>(below_near & active) >= active_count<K>(active);
                        if (top < kStackSize) {
                            stack[top++] = below_first ? Entry<K>{above, above_t0, above_t1}
                                                       : Entry<K>{below, below_t0, below_t1};
                        }
                        index = below_first ? below : above;
                        t0 = below_first ? below_t0 : above_t0;
                        t1 = below_first ? below_t1 : above_t1;
                        active = below_first ? need_below : need_above;
                    }
                }
                // Every active lane needs at least one child, so `active` is never empty here;
                // lanes whose hit is nearer than their new t0 drop out at the next pop.
                node = &tree.nodes[index];
            }
            if (node->is_leaf() && any(active)) {
                const uint32_t first = node->first, count = node->count();
                for (uint32_t i = 0; i < count; ++i) {
                    const uint32_t prim = tree.leaf_prims[first + i];
                    const B got = intersect_triangle<K, kAnyHit>(r, tree.triangles + 9 * size_t(prim),
                                                                 static_cast<int32_t>(prim), active, hit);
                    if (kAnyHit) {
                        occluded = occluded | got;
                        active = andnot(got, active);
                        if (none(active)) break;
                    }
                }
            }
        }
        if (kAnyHit && all(occluded)) return occluded;
        if (top == 0) return occluded;
        const Entry<K>& e = stack[--top];
        index = e.node;
        t0 = e.tmin;
        t1 = min(e.tmax, hit.t);
    }
}

// Closest hit for K rays (hit.t starts at the rays' tmax and stays there on a miss).
template <int K>
PATINA_INLINE void intersect_packet(const TreeView& tree, const RayPacket<K>& r, HitPacket<K>& hit) {
    hit.t = r.tmax;
    hit.u = vfloat<K>(0.0f);
    hit.v = vfloat<K>(0.0f);
    hit.prim = vint<K>(-1);
    if (!tree.spheres->empty()) intersect_spheres<K>(*tree.spheres, r.org, r.dir, r.tmin, hit.t, hit.prim);
    if (!tree.nodes) return;
    vfloat<K> t0, t1;
    traverse_detail::clip_to_box<K>(r, tree.bounds, t0, t1);
    traverse_from<K, false>(tree, r, 0, t0, t1, hit);
}

// Lanes with any hit in (tmin, tmax).
template <int K>
PATINA_INLINE vbool<K> occluded_packet(const TreeView& tree, const RayPacket<K>& r) {
    HitPacket<K> hit;
    hit.t = r.tmax;
    const vbool<K> by_sphere = tree.spheres->empty() ? vbool<K>(false)
                                                     : occluded_by_spheres<K>(*tree.spheres, r.org, r.dir, r.tmin, r.tmax);
    if (!tree.nodes || all(by_sphere)) return by_sphere;
    vfloat<K> t0, t1;
    traverse_detail::clip_to_box<K>(r, tree.bounds, t0, t1);
    // lanes a sphere blocks already have their answer: an empty interval skips them
    t0 = select(by_sphere, vfloat<K>(std::numeric_limits<float>::infinity()), t0);
    return by_sphere | traverse_from<K, true>(tree, r, 0, t0, t1, hit);
}

PATINA_END_TARGET
