// Run-time dispatch to the ray-tracing kernels compiled for each packet width
// (trace_kernels_w1.cpp, trace_kernels_w4.cpp with -msse4.1, trace_kernels_w8.cpp with -mavx2 -mfma).
// kd-tree: rays [i, i + K) of the input arrays form one packet, so the caller's ray order
// decides how coherent packets are. BVH (bvh.h): one ray at a time, the width's lanes over a
// node's children, or (occlusion) packets of rays together; every width gives the same hits.
#pragma once

#include <cstddef>
#include <cstdint>

#include "render/accel/bvh.h"
#include "render/accel/kdtree.h"

namespace patina {

struct RayBatch {
    const float* origins;     // n x 3
    const float* directions;  // n x 3, not necessarily normalised (t is in units of |d|)
    float tmin;
    const float* tmax;  // n values, or nullptr to use tmax_all
    float tmax_all;
};

struct HitBatch {
    float* t;        // n; tmax (inf by default) where nothing is hit
    int32_t* prim;   // n; -1 where nothing is hit
    float* u;        // n; barycentric weight of v1
    float* v;        // n; barycentric weight of v2
};

struct TraceKernels {
    int width;
    void (*intersect)(const KdTree& tree, const RayBatch& rays, const HitBatch& hits, size_t begin, size_t end);
    void (*occluded)(const KdTree& tree, const RayBatch& rays, uint8_t* blocked, size_t begin, size_t end);
    void (*intersect_bvh)(const Bvh& bvh, const RayBatch& rays, const HitBatch& hits, size_t begin, size_t end);
    void (*occluded_bvh)(const Bvh& bvh, const RayBatch& rays, uint8_t* blocked, size_t begin, size_t end);
    // rays [i, i + width) of the input as one packet through the BVH (bvh_packet_occlusion.h)
    void (*occluded_bvh_packets)(const Bvh& bvh, const RayBatch& rays, uint8_t* blocked, size_t begin, size_t end);
};

const TraceKernels& trace_kernels_w1();
const TraceKernels& trace_kernels_w4();
const TraceKernels& trace_kernels_w8();
const TraceKernels& trace_kernels_w16();
const TraceKernels& trace_kernels_for(int width);  // 0 = default; throws std::invalid_argument

// Index of the first ray with a non-finite origin or a zero / non-finite direction, or n.
size_t first_invalid_ray(const RayBatch& rays, size_t n);

// Batches split over threads (0 = all). Unit geometric normals of the hits: n x 3.
void trace_intersect(const KdTree& tree, const RayBatch& rays, const HitBatch& hits, size_t n, int width, int threads);
void trace_occluded(const KdTree& tree, const RayBatch& rays, uint8_t* blocked, size_t n, int width, int threads);
void trace_intersect(const Bvh& bvh, const RayBatch& rays, const HitBatch& hits, size_t n, int width, int threads);
void trace_occluded(const Bvh& bvh, const RayBatch& rays, uint8_t* blocked, size_t n, int width, int threads);
// The same answers as trace_occluded, the rays `width` at a time through the BVH together (for
// coherent rays: neighbouring points towards one light).
void trace_occluded_packets(const Bvh& bvh, const RayBatch& rays, uint8_t* blocked, size_t n, int width, int threads);
// Unit geometric normals of hits (t, prim) of the batch's rays: a triangle's from its winding,
// an analytic sphere's outwards at the hit; 0 on a miss.
void hit_normals(const KdTree& tree, const RayBatch& rays, const float* t, const int32_t* prim, float* normals,
                 size_t n);

}  // namespace patina
