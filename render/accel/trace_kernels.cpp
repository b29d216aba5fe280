#include "render/accel/trace_kernels.h"

#include <cmath>

#include "core/parallel.h"
#include "core/width_dispatch.h"

namespace patina {

const TraceKernels& trace_kernels_for(int width) {
    return kernels_for_width(width, trace_kernels_w1, trace_kernels_w4, trace_kernels_w8, trace_kernels_w16);
}

size_t first_invalid_ray(const RayBatch& rays, size_t n) {
    // One branch-free pass (x - x is 0 exactly for finite x); the slow search only on failure.
    bool ok = true;
    for (size_t i = 0; i < 3 * n; ++i) {
        const float o = rays.origins[i], d = rays.directions[i];
        ok &= (o - o == 0.0f) & (d - d == 0.0f);
    }
    for (size_t i = 0; i < n; ++i) {
        const float* d = rays.directions + 3 * i;
        ok &= (d[0] != 0.0f) | (d[1] != 0.0f) | (d[2] != 0.0f);
        if (rays.tmax) ok &= !std::isnan(rays.tmax[i]);
    }
    if (ok) return n;
    for (size_t i = 0; i < n; ++i) {
        const float* o = rays.origins + 3 * i;
        const float* d = rays.directions + 3 * i;
        bool good = std::isfinite(o[0]) && std::isfinite(o[1]) && std::isfinite(o[2]) && std::isfinite(d[0]) &&
                    std::isfinite(d[1]) && std::isfinite(d[2]) && (d[0] != 0.0f || d[1] != 0.0f || d[2] != 0.0f);
        if (rays.tmax) good = good && !std::isnan(rays.tmax[i]);
        if (!good) return i;
    }
    return n;
}

namespace {
// Runs one of the width's kernels (a member of TraceKernels) over rays [0, n) of a tree or
// a BVH, in blocks of 64 rays or more shared among `threads` workers.
template <class Kernel, class Structure, class Out>
void run_kernel(Kernel TraceKernels::*kernel, const Structure& s, const RayBatch& rays, const Out& out, size_t n,
                int width, int threads) {
    const Kernel k = trace_kernels_for(width).*kernel;
    parallel_for(n, 64, threads, [&](size_t b, size_t e) { k(s, rays, out, b, e); });
}
}  // namespace

void trace_intersect(const KdTree& tree, const RayBatch& rays, const HitBatch& hits, size_t n, int width, int threads) {
    run_kernel(&TraceKernels::intersect, tree, rays, hits, n, width, threads);
}

void trace_occluded(const KdTree& tree, const RayBatch& rays, uint8_t* blocked, size_t n, int width, int threads) {
    run_kernel(&TraceKernels::occluded, tree, rays, blocked, n, width, threads);
}

void trace_intersect(const Bvh& bvh, const RayBatch& rays, const HitBatch& hits, size_t n, int width, int threads) {
    run_kernel(&TraceKernels::intersect_bvh, bvh, rays, hits, n, width, threads);
}

void trace_occluded(const Bvh& bvh, const RayBatch& rays, uint8_t* blocked, size_t n, int width, int threads) {
    run_kernel(&TraceKernels::occluded_bvh, bvh, rays, blocked, n, width, threads);
}

void trace_occluded_packets(const Bvh& bvh, const RayBatch& rays, uint8_t* blocked, size_t n, int width, int threads) {
    run_kernel(&TraceKernels::occluded_bvh_packets, bvh, rays, blocked, n, width, threads);
}

void hit_normals(const KdTree& tree, const RayBatch& rays, const float* t, const int32_t* prim, float* normals,
                 size_t n) {
    const SphereSet& spheres = tree.spheres;
    for (size_t i = 0; i < n; ++i) {
        float* out = normals + 3 * i;
        if (prim[i] < 0) {
            out[0] = out[1] = out[2] = 0.0f;
        } else if (spheres.owns(prim[i])) {
            const size_t k = static_cast<size_t>(prim[i] - spheres.prim_base);
            const float c[3] = {spheres.centre_x[k], spheres.centre_y[k], spheres.centre_z[k]};
            float len2 = 0.0f;
            for (int a = 0; a < 3; ++a) {
                out[a] = rays.origins[3 * i + a] + t[i] * rays.directions[3 * i + a] - c[a];
                len2 += out[a] * out[a];
            }
            const float len = std::sqrt(len2);
            for (int a = 0; a < 3; ++a) out[a] = len > 0.0f ? out[a] / len : 0.0f;
        } else {
            const float* nrm = &tree.normals[3 * size_t(prim[i])];
            out[0] = nrm[0];
            out[1] = nrm[1];
            out[2] = nrm[2];
        }
    }
}

}  // namespace patina
