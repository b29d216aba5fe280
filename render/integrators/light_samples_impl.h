// Light sampling with MIS (an integrator's stage): one light sample per shading point, the
// BSDF evaluated for it N points of a material at a time, its shadow ray queued with what it
// adds if unblocked; then the shadow rays traced as packets and the unblocked ones' light added.
#pragma once

#include <algorithm>

#include "core/constants.h"
#include "core/simd/kernel_width.h"
#include "render/integrators/integrator.h"
#include "render/integrators/shading_points_impl.h"
#include "render/integrators/shadow_rays_impl.h"
#include "render/integrators/wavefront_impl.h"
#include "render/lights/sampling_impl.h"
#include "render/materials/material_impl.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// Veach's power heuristic (power_heuristic) N at a time, the same operations lane by lane.
PATINA_INLINE F power_heuristic_lanes(F a, F b) {
    const F r = b / a;
    return select(!(a > F(0.0f)), F(0.0f), select(!(b > F(0.0f)), F(1.0f), F(1.0f) / (F(1.0f) + r * r)));
}

// std::max and std::min lane by lane (the second argument where the first does not compare:
// the scalar code's NaN behaviour too).
PATINA_INLINE F std_max(F a, F b) { return select(a < b, b, a); }
PATINA_INLINE F std_min(F a, F b) { return select(b < a, b, a); }

// The lanes whose bit is set in `bits`, as a mask.
PATINA_INLINE B mask_of_bits(int bits) {
    constexpr int32_t kBit[16] = {1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384, 32768};
    const I bit = load_n<N>(kBit);
    return (I(bits) & bit) == bit;
}

// N path numbers from an (n,) array, the last block's padding lanes path 0 (read, never written).
PATINA_INLINE I load_path_lanes(const int32_t* p, size_t i, int lanes) {
    if (lanes == N) return load_n<N>(p + i);
    alignas(64) int32_t pad[N] = {};
    std::copy(p + i, p + i + lanes, pad);
    return load_n<N>(pad);
}

// The light samples' shadow rays, N points at a time: each lane's contribution (throughput x
// BRDF x cosine x radiance x MIS weight / pdf), lux and ray with queue_shadow_ray's operations,
// and the lanes that carry light written to the queue in point order (a compress-store);
// `share`: the sample's weight among the point's light samples (1: the only one).
inline void queue_shadow_lanes(const Wavefront& wavefront, int depth, size_t np, float share) {
    PathScratch& scratch = wavefront.scratch;
    const float* ll = scratch.l_local.data();
    const float* fv = scratch.bsdf_rgb.data();
    const float* pdf = scratch.pdf.data();
    resize_shadow_rays(scratch, np);
    size_t m = 0;
    for_blocks(np, [&](size_t q0, int lanes) {
        int ok_bits = 0, delta_bits = 0;
        for (int k = 0; k < lanes; ++k) {
            ok_bits |= (scratch.light_samples.usable[q0 + k] ? 1 : 0) << k;
            delta_bits |= (scratch.light_samples.delta[q0 + k] ? 1 : 0) << k;
        }
        if (ok_bits == 0) return;
        const V3 L = load_rows(ll, q0, lanes), FV = load_rows(fv, q0, lanes),
                 RGB = load_rows(scratch.light_samples.rgb.data(), q0, lanes);
        const F z = L.z, lp = load_lanes(scratch.light_samples.pdf.data(), q0, lanes), cos_l = abs(z);
        const I path3 = load_path_lanes(scratch.point_lanes.path.data(), q0, lanes) * I(3);
        const float* thr = scratch.throughput.data();
        const F wt = select(mask_of_bits(delta_bits), F(1.0f), power_heuristic_lanes(lp, load_lanes(pdf, q0, lanes)));
        const F c[3] = {gather(thr, path3) * FV.x * cos_l * RGB.x * wt / lp * F(share),
                        gather(thr, path3 + I(1)) * FV.y * cos_l * RGB.y * wt / lp * F(share),
                        gather(thr, path3 + I(2)) * FV.z * cos_l * RGB.z * wt / lp * F(share)};
        const B front = z > F(0.0f);
        const F lum = F(0.2126f) * RGB.x + F(0.7152f) * RGB.y + F(0.0722f) * RGB.z;
        const F lux = depth == 0 ? select(front, F(kLumensPerWatt) * lum * cos_l / lp * F(share), F(0.0f)) : F(0.0f);
        const F side = select(front, F(wavefront.ray_offset), F(-wavefront.ray_offset));
        const B none_carried = (c[0] <= F(0.0f)) & (c[1] <= F(0.0f)) & (c[2] <= F(0.0f)) & (lux <= F(0.0f));
        const B queued = (cos_l > F(0.0f)) & !none_carried;
        // queue_shadow_ray: from the lifted origin, aimed at the light's point unless at infinity
        const V3 P = load_rows(scratch.point_lanes.position.data(), q0, lanes),
                 D = load_rows(scratch.light_samples.dir.data(), q0, lanes);
        const F ds = load_lanes(scratch.light_samples.dist.data(), q0, lanes);
        const V3 o = P + side * load_rows(scratch.point_lanes.geometric_normal.data(), q0, lanes);
        const V3 to = P + ds * D - o;
        const F len = sqrt_exact(dot(to, to));
        const B finite = !(abs(ds) == F(kInfinity));
        const V3 d = select3(finite, V3{to.x / len, to.y / len, to.z / len}, D);
        const F tmax = select(finite, len * F(1.0f - 1e-4f), F(kInfinity));
        alignas(64) float oo[3][N], dd[3][N], cc[3][N], tt[N], lx[N];
        for (int k = 0; k < 3; ++k) {
            store_n<N>(cc[k], c[k]);
        }
        store_lanes3(oo, o);
        store_lanes3(dd, d);
        store_n<N>(tt, tmax);
        store_n<N>(lx, lux);
        for (int bits = movemask(queued) & ok_bits; bits; bits &= bits - 1) {
            const int k = __builtin_ctz(static_cast<unsigned>(bits));
            scratch.shadow_rays.path[m] = scratch.point_lanes.path[q0 + k];
            for (int a = 0; a < 3; ++a) {
                scratch.shadow_rays.org[3 * m + a] = oo[a][k];
                scratch.shadow_rays.dir[3 * m + a] = dd[a][k];
                scratch.shadow_rays.rgb[3 * m + a] = cc[a][k];
            }
            scratch.shadow_rays.tmax[m] = tt[k];
            scratch.shadow_rays.lux[m] = lx[k];
            ++m;
        }
    });
    resize_shadow_rays(scratch, m);
}

// Light sampling: one light sample per shading point, in the point's frame; the BSDF
// evaluated for it and its density under BSDF sampling (for the MIS weight), N points of a
// material at a time. False when no light can light anything (then no shadow ray is queued).
inline bool sample_and_evaluate_lights(const Wavefront& wavefront, int depth) {
    PathScratch& scratch = wavefront.scratch;
    clear_shadow_rays(scratch);
    if (!wavefront.can_sample_lights) return false;
    const size_t np = scratch.sorted.size();
    const MaterialBuffers buffers = material_buffers(scratch);
    sample_lights(wavefront.scene, scratch, depth, np);
    for (size_t q = 0; q < np; ++q) {
        const ShadingPoint& sp = scratch.sorted[q];
        const Vec3f ldir = load_vec3(scratch.light_samples.dir.data() + 3 * q);
        const Vec3f l = scratch.light_samples.usable[q] ? to_local(sp, ldir) : Vec3f{0, 0, 0};
        store_vec3(l, buffers.light_local + 3 * q);
        // the light must be on the side the local direction says (shading normals bend)
        const float side = dot(ldir, sp.ng);
        const bool transmissive = transmits(wavefront.scene.materials[sp.material]);
        scratch.light_samples.usable[q] = scratch.light_samples.usable[q] && (transmissive ? side * l.z > 0 : side > 0);
    }
    scratch.timer.lap(Stage::LightToLocal);
    for_material_groups(wavefront, [&](const Material& m, size_t a, size_t count) {
        const MaterialBuffers group = buffers.from(a);
        material_eval(m, group.light_local, group.view_local, group.eta, group.bsdf_rgb, count);
        material_pdf(m, group.light_local, group.view_local, group.eta, group.pdf, count);
    });
    return true;
}

// The light samples' shadow rays queued, each with what it adds if unblocked: throughput x
// BSDF x cosine x radiance x MIS weight / pdf x share (and, at the first hit, the illuminance AOV).
inline void queue_light_shadow_rays(const Wavefront& wavefront, int depth, float share) {
    PathScratch& scratch = wavefront.scratch;
    scratch.timer.lap(Stage::ShadeLight);
    queue_shadow_lanes(wavefront, depth, scratch.sorted.size(), share);
    scratch.timer.lap(Stage::ShadowQueue);
}

// Light sampling with MIS, its shadow rays queued (resolved by resolve_shadow_rays); `share`:
// the sample's weight when a point takes several (first_hit_light_samples_impl.h).
inline void queue_light_samples(const Wavefront& wavefront, int depth, float share = 1.0f) {
    if (sample_and_evaluate_lights(wavefront, depth)) queue_light_shadow_rays(wavefront, depth, share);
}

// The queued shadow rays, N per packet; the unblocked ones add their light.
inline void resolve_shadow_rays(const Wavefront& wavefront) {
    PathScratch& scratch = wavefront.scratch;
    const uint8_t* blocked = trace_shadow_rays(wavefront.scene, scratch);
    scratch.timer.times.shadow_rays += scratch.shadow_rays.path.size();
    scratch.timer.lap(Stage::TraceShadow);
    for (size_t q = 0; q < scratch.shadow_rays.path.size(); ++q) {
        if (blocked[q]) continue;
        PathResult& r = wavefront.results[scratch.shadow_rays.path[q]];
        for (int k = 0; k < 3; ++k) r.rgb[k] += scratch.shadow_rays.rgb[3 * q + k];
        r.illuminance += scratch.shadow_rays.lux[q];
    }
    scratch.timer.lap(Stage::ShadowResolve);
}

}  // namespace render_detail
PATINA_END_TARGET
