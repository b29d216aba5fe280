// The body of trace_kernels_w{1,4,8}.cpp: defines trace_kernels_wN() for PATINA_KERNEL_WIDTH.
#pragma once

#include <algorithm>

#include "core/constants.h"
#include "core/simd/kernel_width.h"
#include "render/accel/bvh_packet_occlusion.h"
#include "render/accel/bvh_traverse.h"
#include "render/accel/ray_recorder.h"
#include "render/accel/trace_kernels.h"
#include "render/accel/trace_kernels_bvh_rays.h"
#include "render/accel/traverse.h"

PATINA_BEGIN_TARGET
namespace {
using namespace kernel_width;  // N rays per packet: the traversal's K is N here

// Loads rays [i, i + lanes) as one packet; missing lanes get an empty interval.
RayPacket<N> load_packet(const RayBatch& rays, size_t i, int lanes) {
    RayPacket<N> r;
    float org[3 * N], dir[3 * N], tmax[N];
    const float* o = rays.origins + 3 * i;
    const float* d = rays.directions + 3 * i;
    if (lanes < N) {
        for (int j = 0; j < N; ++j) {
            const bool real = j < lanes;
            for (int a = 0; a < 3; ++a) {
                org[3 * j + a] = real ? o[3 * j + a] : 0.0f;
                dir[3 * j + a] = real ? d[3 * j + a] : (a == 2 ? 1.0f : 0.0f);
            }
            tmax[j] = real ? (rays.tmax ? rays.tmax[i + j] : rays.tmax_all) : -1.0f;
        }
        o = org;
        d = dir;
    }
    load_xyz(o, r.org[0], r.org[1], r.org[2]);
    load_xyz(d, r.dir[0], r.dir[1], r.dir[2]);
    r.tmin = F(rays.tmin);
    if (lanes < N) r.tmax = load_n<N>(tmax);
    else r.tmax = rays.tmax ? load_n<N>(rays.tmax + i) : F(rays.tmax_all);
    prepare_packet<N>(r);
    return r;
}

void intersect_kernel(const KdTree& tree, const RayBatch& rays, const HitBatch& hits, size_t begin, size_t end) {
    enter_kernel();
    if (ray_recording_on()) record_rays(rays, begin, end, false);
    const TreeView view = tree_view(tree);
    for (size_t i = begin; i < end; i += N) {
        const int lanes = static_cast<int>(std::min<size_t>(N, end - i));
        const RayPacket<N> r = load_packet(rays, i, lanes);
        HitPacket<N> h;
        intersect_packet<N>(view, r, h);
        alignas(32) float t[N], u[N], v[N];
        alignas(32) int32_t prim[N];
        store_n<N>(t, h.t);
        store_n<N>(u, h.u);
        store_n<N>(v, h.v);
        store_n<N>(prim, h.prim);
        for (int j = 0; j < lanes; ++j) {
            hits.t[i + j] = prim[j] >= 0 ? t[j] : kInfinity;
            hits.prim[i + j] = prim[j];
            hits.u[i + j] = u[j];
            hits.v[i + j] = v[j];
        }
    }
}

// Rays [begin, end) N at a time as packets, blocked[i] from occluded(packet)'s lanes.
template <class Occluded>
PATINA_INLINE void occluded_packets(const RayBatch& rays, uint8_t* blocked, size_t begin, size_t end,
                                    Occluded&& occluded) {
    enter_kernel();
    if (ray_recording_on()) record_rays(rays, begin, end, true);
    for (size_t i = begin; i < end; i += N) {
        const int lanes = static_cast<int>(std::min<size_t>(N, end - i));
        const RayPacket<N> r = load_packet(rays, i, lanes);
        const int mask = movemask(occluded(r));
        for (int j = 0; j < lanes; ++j) blocked[i + j] = static_cast<uint8_t>((mask >> j) & 1);
    }
}

void occluded_kernel(const KdTree& tree, const RayBatch& rays, uint8_t* blocked, size_t begin, size_t end) {
    const TreeView view = tree_view(tree);
    occluded_packets(rays, blocked, begin, end, [&](const RayPacket<N>& r) { return occluded_packet<N>(view, r); });
}

void occluded_bvh_packet_kernel(const Bvh& bvh, const RayBatch& rays, uint8_t* blocked, size_t begin, size_t end) {
    occluded_packets(rays, blocked, begin, end, [&](const RayPacket<N>& r) { return bvh_occluded_packet<N>(bvh, r); });
}

// The BVH's lanes: its nodes' eight children, a block's eight triangles, at most N at a time.
constexpr int kNodeLanes = N < kBvhWidth ? N : kBvhWidth;
constexpr int kBlockLanes = N < kBvhBlock ? N : kBvhBlock;

// Rays [begin, end) of the batch one at a time through the BVH, set up N at a time:
// spheres(lanes_of) for each N (the analytic spheres' tests, in the lanes), and the root node's
// children tested for the N rays at once; then trace(i, j, r, b, root) for each ray (i in the
// batch, lane j; root null when the root is not an interior node), or miss(i, j) instead for a
// ray that enters none of the root's children (its spheres' result is all it has).
template <class Spheres, class Trace, class Miss>
PATINA_INLINE void for_each_bvh_ray(const Bvh& bvh, const RayBatch& rays, size_t begin, size_t end, Spheres&& spheres,
                                    Trace&& trace, Miss&& miss) {
    BvhRayLanes<N> lanes_of;
    BvhRootLanes<N> root_of;
    const bool interior_root = bvh.root != kBvhEmpty && !bvh_is_leaf(bvh.root);
    for (size_t i = begin; i < end; i += N) {
        const int lanes = static_cast<int>(std::min<size_t>(N, end - i));
        load_bvh_rays<N>(bvh, rays, i, lanes, lanes_of);
        spheres(lanes_of);
        if (interior_root) test_root_children<N>(bvh, lanes_of, rays.tmin, root_of);
        for (int j = 0; j < lanes; ++j) {
            alignas(32) float near[kBvhWidth];
            bvh_detail::RootHits root{interior_root ? root_of.mask[j] : 0, near};
            if (interior_root && root.mask == 0) {
                miss(i + j, j);
                continue;
            }
            for (int c = 0; c < kBvhWidth; ++c) near[c] = root_of.near[c][j];
            RayPacket<1> r;
            bvh_detail::BoxRay b;
            bvh_ray_of<N>(lanes_of, j, rays.tmin, r, b);
            trace(i + j, j, r, b, interior_root ? &root : nullptr);
        }
    }
}

void intersect_bvh_kernel(const Bvh& bvh, const RayBatch& rays, const HitBatch& hits, size_t begin, size_t end) {
    enter_kernel();
    if (ray_recording_on()) record_rays(rays, begin, end, false);
    alignas(64) float sphere_t[N];
    alignas(64) int32_t sphere_prim[N];
    const auto spheres = [&](const BvhRayLanes<N>& l) {
        F t = load_n<N>(l.tmax);
        I prim(-1);
        if (!bvh.spheres.empty()) {
            F org[3], dir[3];
            l.rays(org, dir);
            intersect_spheres<N>(bvh.spheres, org, dir, F(rays.tmin), t, prim);
        }
        store_n<N>(sphere_t, t);
        store_n<N>(sphere_prim, prim);
    };
    const auto write = [&](size_t i, const HitPacket<1>& h) {
        hits.t[i] = h.prim >= 0 ? h.t : kInfinity;
        hits.prim[i] = h.prim;
        hits.u[i] = h.u;
        hits.v[i] = h.v;
    };
    for_each_bvh_ray(
        bvh, rays, begin, end, spheres,
        [&](size_t i, int j, const RayPacket<1>& r, const bvh_detail::BoxRay& b, const bvh_detail::RootHits* root) {
            HitPacket<1> h{sphere_t[j], 0.0f, 0.0f, sphere_prim[j]};
            bvh_intersect_triangles<kNodeLanes, kBlockLanes>(bvh, r, b, h, root);
            write(i, h);
        },
        [&](size_t i, int j) { write(i, HitPacket<1>{sphere_t[j], 0.0f, 0.0f, sphere_prim[j]}); });
}

void occluded_bvh_kernel(const Bvh& bvh, const RayBatch& rays, uint8_t* blocked, size_t begin, size_t end) {
    enter_kernel();
    if (ray_recording_on()) record_rays(rays, begin, end, true);
    int by_sphere = 0;  // bit j: lane j's ray is blocked by a sphere
    const auto spheres = [&](const BvhRayLanes<N>& l) {
        if (bvh.spheres.empty()) return;
        F org[3], dir[3];
        l.rays(org, dir);
        by_sphere = movemask(occluded_by_spheres<N>(bvh.spheres, org, dir, F(rays.tmin), load_n<N>(l.tmax)));
    };
    for_each_bvh_ray(
        bvh, rays, begin, end, spheres,
        [&](size_t i, int j, const RayPacket<1>& r, const bvh_detail::BoxRay& b, const bvh_detail::RootHits* root) {
            blocked[i] = static_cast<uint8_t>(((by_sphere >> j) & 1) ||
                                              bvh_occluded_triangles<kNodeLanes, kBlockLanes>(bvh, r, b, root));
        },
        [&](size_t i, int j) { blocked[i] = static_cast<uint8_t>((by_sphere >> j) & 1); });
}

}  // namespace
PATINA_END_TARGET
