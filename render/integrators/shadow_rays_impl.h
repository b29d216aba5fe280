// Shadow rays: the light samples' rays queued as points are shaded, then traced together as
// packets of N (any hit), each unblocked one adding the light its owner queued it with.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "core/constants.h"
#include "core/simd/kernel_width.h"
#include "core/vec3.h"
#include "core/width_dispatch.h"
#include "render/accel/trace_kernels.h"
#include "render/integrators/integrator.h"
#include "render/lights/sampling_impl.h"
#include "render/scene.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// The ray-tracing kernels compiled for this width: N rays per packet.
inline const TraceKernels& trace_kernels() {
    return kernels_at_width<N>(trace_kernels_w1, trace_kernels_w4, trace_kernels_w8, trace_kernels_w16);
}

// Queues the shadow ray of a light sample taken at p: from p lifted by `offset` along n to
// the light's point (or to infinity), carrying the radiance `rgb` and illuminance `lux` it
// adds to path `owner` if nothing is in the way.
inline void queue_shadow_ray(PathScratch& scratch, int32_t owner, const Vec3f& p, const Vec3f& n, float offset,
                             const LightSample& ls, const float* rgb, float lux) {
    const Vec3f o = p + offset * n;
    Vec3f d = ls.dir;
    float tmax = kInfinity;
    if (!std::isinf(ls.dist)) {
        // aim from the lifted origin at the light's point: seen at a grazing angle, an origin
        // lifted off the surface is much nearer the light than `dist` says
        const Vec3f to = p + ls.dist * ls.dir - o;
        const float len = std::sqrt(dot(to, to));
        d = Vec3f{to.x / len, to.y / len, to.z / len};
        tmax = len * (1.0f - 1e-4f);
    }
    ShadowRayQueue& queue = scratch.shadow_rays;
    queue.path.push_back(owner);
    queue.org.insert(queue.org.end(), {o.x, o.y, o.z});
    queue.dir.insert(queue.dir.end(), {d.x, d.y, d.z});
    queue.rgb.insert(queue.rgb.end(), rgb, rgb + 3);
    queue.tmax.push_back(tmax);
    queue.lux.push_back(lux);
}

// The queue n rays long (a stage that writes them in place, then cuts it to the rays it wrote).
inline void resize_shadow_rays(PathScratch& scratch, size_t n) {
    ShadowRayQueue& queue = scratch.shadow_rays;
    queue.path.resize(n);
    queue.org.resize(3 * n);
    queue.dir.resize(3 * n);
    queue.rgb.resize(3 * n);
    queue.tmax.resize(n);
    queue.lux.resize(n);
}

inline void clear_shadow_rays(PathScratch& scratch) {
    ShadowRayQueue& queue = scratch.shadow_rays;
    queue.path.clear();
    queue.org.clear();
    queue.dir.clear();
    queue.tmax.clear();
    queue.rgb.clear();
    queue.lux.clear();
}

// Traces the queued shadow rays (through the BVH if the scene has one, else N per kd-tree
// packet); returns scratch.shadow_rays.blocked (one byte per ray).
inline const uint8_t* trace_shadow_rays(const RenderScene& scene, PathScratch& scratch) {
    ShadowRayQueue& queue = scratch.shadow_rays;
    const size_t ns = queue.path.size();
    uint8_t* blocked = grow(queue.blocked, ns);
    if (ns > 0) {
        const RayBatch rays{queue.org.data(), queue.dir.data(), 0.0f, queue.tmax.data(), kInfinity};
        if (scene.bvh)
            trace_kernels().occluded_bvh(*scene.bvh, rays, blocked, 0, ns);
        else
            trace_kernels().occluded(*scene.tree, rays, blocked, 0, ns);
        scratch.rays_traced += ns;
    }
    return blocked;
}

}  // namespace render_detail
PATINA_END_TARGET
