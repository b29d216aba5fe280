// The radiance cache at one point reprojected into another (integrator.h, cache_probe): what
// docs/radiance-cache.md's pictures and the reprojection tests look at.
#pragma once

#include <algorithm>
#include <vector>

#include "core/simd/kernel_width.h"
#include "render/cache/cache_probe.h"
#include "render/cache/cache_stages_impl.h"
#include "render/integrators/cache_impl.h"
#include "render/integrators/integrator.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// The radiance cache at one point reprojected into another (render/integrators/integrator.h, cache_probe).
void cache_probe(const RenderScene& scene, const IntegratorSettings& settings, const float* pa, const float* na,
                 const float* pb, const float* nb, uint32_t seed, bool unknown_masks, CacheProbe& out) {
    enter_kernel();
    const CacheSettings& cfg = settings.cache;
    check_cache_settings(cfg);
    const int R = cfg.resolution;
    const size_t texel_count = static_cast<size_t>(R) * R;
    PathScratch scratch;
    cache::CacheState& state = cache::cache_state(scratch);
    IntegratorSettings inner = settings;
    inner.mode = IntegratorMode::Path;
    inner.indirect_illuminance = false;
    inner.max_depth = std::max(1, settings.max_depth - 1);
    inner.rr_depth = std::max(1, settings.rr_depth - 1);
    auto tracer = [&](const float* o, const float* d, const uint32_t* k, const uint32_t* idx, size_t m, PathResult* r) {
        trace_given_rays(scene, inner, o, d, k, idx, m, r, state.inner, state.inner_samples);
    };
    auto query = [&](const float* p, const float* n, uint32_t key) {
        cache::Query q;
        q.p = load_vec3(p);
        q.n = q.ng = normalize(load_vec3(n));
        orthonormal_frame(q.n, q.t, q.b);
        q.key = key;
        return q;
    };
    const cache::Query q[2] = {query(pa, na, hash_u32(seed)), query(pb, nb, hash_u32(seed + 1))};
    state.texel_directions.prepare(R);
    IntegratorSettings as_cache = settings;  // A's glossy texel hits split as `cache` splits them
    as_cache.mode = IntegratorMode::Cache;
    cache::mark_split_materials(scene.materials, as_cache, state);
    // A, then B's own hemisphere in full (the reference)
    state.build.used = 0;
    state.build.pending = {0, 1};
    cache::build_cache_points(cfg, scene.ray_offset, q, state, tracer);
    const CachePoint& a = state.build.points[0];
    out = CacheProbe{};
    out.resolution = R;
    out.a_radiance = a.radiance;
    out.a_dist = a.dist;
    out.a_kind = a.kind;
    out.a_layer.assign(texel_count, -1);
    out.a_surfel.assign(texel_count, -1);
    for (size_t k = 0; k < a.surfels.size(); ++k) {
        const Surfel& sf = a.surfels[k];
        for (int j = sf.j0; j < sf.j1; ++j)
            for (int i = sf.i0; i < sf.i1; ++i) {
                out.a_layer[static_cast<size_t>(j) * R + i] = sf.layer;
                out.a_surfel[static_cast<size_t>(j) * R + i] = static_cast<int32_t>(k);
            }
    }
    out.surfels = a.surfels.size();
    out.silhouettes = a.silhouettes.size();
    out.b_reference = state.build.points[1].radiance;
    // B by reprojection, its holes traced
    out.b_reprojected.assign(3 * texel_count, -1.0f);
    cache::Reprojection& reprojected = state.reprojection.from_assigned;
    cache::reproject(a, cache::Receiver{q[1].p, q[1].t, q[1].b, q[1].n}, state.texel_directions,
                     out.b_reprojected.data(), reprojected, state.reprojection.scratch, unknown_masks);
    out.filled.assign(texel_count, 0);
    out.unknown.assign(texel_count, 0);
    out.to_trace.assign(texel_count, 0);
    out.b_radiance = out.b_reprojected;
    cache::RayQueue& rays = state.build.rays;
    rays.clear();
    const uint32_t key = cache::hole_key(q[1].key);
    for (size_t t = 0; t < texel_count; ++t) {
        const int x = static_cast<int>(t % R), y = static_cast<int>(t / R);
        out.filled[t] = reprojected.filled.test(x, y);
        out.unknown[t] = reprojected.unknown.test(x, y);
        out.to_trace[t] = reprojected.to_trace.test(x, y);
        if (!out.to_trace[t]) continue;
        std::fill(out.b_reprojected.begin() + 3 * t, out.b_reprojected.begin() + 3 * t + 3, -1.0f);
        std::fill(out.b_radiance.begin() + 3 * t, out.b_radiance.begin() + 3 * t + 3, 0.0f);
        const Vec3f d = cache::jittered_direction(q[1], R, static_cast<int32_t>(t), key);
        if (dot(d, q[1].ng) > 0)
            rays.push(q[1].p + scene.ray_offset * q[1].ng, d, key, static_cast<uint32_t>(t), static_cast<int32_t>(t));
    }
    cache::trace_queue(state, tracer);
    for (size_t r = 0; r < rays.size(); ++r)
        std::copy(state.build.results[r].rgb, state.build.results[r].rgb + 3, out.b_radiance.data() + 3 * rays.where[r]);
}

}  // namespace render_detail
PATINA_END_TARGET
