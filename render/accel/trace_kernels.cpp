#include "render/accel/trace_kernels.h"

#include <cmath>

#include "core/cpu.h"
#include "core/parallel.h"

namespace patina {

const TraceKernels& trace_kernels_for(int width) {
    switch (resolve_width(width)) {
        case 8: return trace_kernels_w8();
        case 4: return trace_kernels_w4();
        default: return trace_kernels_w1();
    }
}

size_t first_invalid_ray(const RayBatch& rays, size_t n) {
    for (size_t i = 0; i < n; ++i) {
        const float* o = rays.origins + 3 * i;
        const float* d = rays.directions + 3 * i;
        bool ok = std::isfinite(o[0]) && std::isfinite(o[1]) && std::isfinite(o[2]) && std::isfinite(d[0]) &&
                  std::isfinite(d[1]) && std::isfinite(d[2]) && (d[0] != 0.0f || d[1] != 0.0f || d[2] != 0.0f);
        if (rays.tmax) ok = ok && !std::isnan(rays.tmax[i]);
        if (!ok) return i;
    }
    return n;
}

void trace_intersect(const KdTree& tree, const RayBatch& rays, const HitBatch& hits, size_t n, int width, int threads) {
    const TraceKernels& k = trace_kernels_for(width);
    parallel_for(n, 64, threads, [&](size_t b, size_t e) { k.intersect(tree, rays, hits, b, e); });
}

void trace_occluded(const KdTree& tree, const RayBatch& rays, uint8_t* blocked, size_t n, int width, int threads) {
    const TraceKernels& k = trace_kernels_for(width);
    parallel_for(n, 64, threads, [&](size_t b, size_t e) { k.occluded(tree, rays, blocked, b, e); });
}

void hit_normals(const KdTree& tree, const int32_t* prim, float* normals, size_t n) {
    for (size_t i = 0; i < n; ++i) {
        float* out = normals + 3 * i;
        if (prim[i] < 0) {
            out[0] = out[1] = out[2] = 0.0f;
            continue;
        }
        const float* t = &tree.triangles[9 * size_t(prim[i])];
        const double e1[3] = {double(t[3]) - t[0], double(t[4]) - t[1], double(t[5]) - t[2]};
        const double e2[3] = {double(t[6]) - t[0], double(t[7]) - t[1], double(t[8]) - t[2]};
        const double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        const double len = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        for (int a = 0; a < 3; ++a) out[a] = len > 0 ? static_cast<float>(c[a] / len) : 0.0f;
    }
}

}  // namespace patina
