// BSDF sampling (an integrator's stage): each shading point's next direction, N points of a
// material at a time; the path's throughput, Russian roulette, and the next bounce's rays.
#pragma once

#include <algorithm>

#include "core/simd/kernel_width.h"
#include "render/integrators/integrator.h"
#include "render/integrators/light_samples_impl.h"
#include "render/integrators/shading_points_impl.h"
#include "render/integrators/wavefront_impl.h"
#include "render/materials/material_impl.h"
#include "render/samplers/sample_numbers.h"
#include "render/samplers/uniforms_impl.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// The paths after their BRDF samples, N points at a time, each lane with the one-point
// operations: the direction into the world (on the side the local direction says), the
// throughput times BRDF x cosine / pdf, Russian roulette, and the next ray of the paths that
// go on, appended to scratch.next_active in point order.
inline void update_paths(const Wavefront& wavefront, int depth, size_t np) {
    PathScratch& scratch = wavefront.scratch;
    const float* ll = scratch.l_local.data();
    const float* fv = scratch.bsdf_rgb.data();
    const float* pdf = scratch.pdf.data();
    const bool roulette = depth + 1 >= wavefront.settings.rr_depth;
    scratch.next_active.resize(np);
    float* next_org = grow(scratch.next_ray_org, 3 * np);
    float* next_dir = grow(scratch.next_ray_dir, 3 * np);
    size_t m = 0;
    for_blocks(np, [&](size_t q0, int lanes) {
        const I path = load_path_lanes(scratch.point_lanes.path.data(), q0, lanes), path3 = path * I(3);
        alignas(64) int32_t key[N] = {}, index[N] = {};
        uint32_t all = 0;
        if (roulette)
            for (int k = 0; k < lanes; ++k) {
                const CameraSample& c = wavefront.camera_samples[scratch.point_lanes.path[q0 + k]];
                key[k] = static_cast<int32_t>(c.key);
                index[k] = static_cast<int32_t>(c.index);
                all |= c.index;
            }
        const V3 L = load_rows(ll, q0, lanes);
        const F P = load_lanes(pdf, q0, lanes);
        B go = (P > F(0.0f)) & (L.z != F(0.0f));
        // to_world(sp, l), normalised
        const V3 wl = normalize_lanes(L.x * load_rows(scratch.point_lanes.tangent.data(), q0, lanes) +
                                      L.y * load_rows(scratch.point_lanes.bitangent.data(), q0, lanes) +
                                      L.z * load_rows(scratch.point_lanes.normal.data(), q0, lanes));
        const V3 NG = load_rows(scratch.point_lanes.geometric_normal.data(), q0, lanes);
        const V3 FV = load_rows(fv, q0, lanes);
        go = go & (dot(wl, NG) * L.z > F(0.0f));  // the side the local direction says
        const float* thr = scratch.throughput.data();
        F T[3] = {gather(thr, path3) * (FV.x * abs(L.z) / P), gather(thr, path3 + I(1)) * (FV.y * abs(L.z) / P),
                  gather(thr, path3 + I(2)) * (FV.z * abs(L.z) / P)};
        // the throughput as the path left it (a path that ends below keeps the product)
        const int updated = movemask(go) & ((1 << lanes) - 1);
        go = go & ((T[0] > F(0.0f)) | (T[1] > F(0.0f)) | (T[2] > F(0.0f)));
        if (roulette) {
            const F survive = std_min(F(0.95f), std_max(T[0], std_max(T[1], T[2])));
            const F u = sample_uniform_lanes(wavefront.settings.sampler, load_n<N>(key), load_n<N>(index),
                                             bit_length(all), depth, kDimRoulette);
            const B lives = go & !(u >= survive);
            for (int c = 0; c < 3; ++c) T[c] = select(lives, T[c] / survive, T[c]);
            go = lives;
        }
        const F side = select(L.z > F(0.0f), F(wavefront.ray_offset), F(-wavefront.ray_offset));
        const V3 Pp = load_rows(scratch.point_lanes.position.data(), q0, lanes);
        const V3 o = Pp + side * NG;
        alignas(64) float tt[3][N], oo[3][N], dd[3][N], pp[3][N];
        for (int c = 0; c < 3; ++c) store_n<N>(tt[c], T[c]);
        store_lanes3(pp, Pp);
        store_lanes3(oo, o);
        store_lanes3(dd, wl);
        for (int bits = updated; bits; bits &= bits - 1) {
            const int k = __builtin_ctz(static_cast<unsigned>(bits));
            float* Tk = scratch.throughput.data() + 3 * scratch.point_lanes.path[q0 + k];
            for (int c = 0; c < 3; ++c) Tk[c] = tt[c][k];
        }
        for (int bits = movemask(go) & ((1 << lanes) - 1); bits; bits &= bits - 1) {
            const int k = __builtin_ctz(static_cast<unsigned>(bits));
            const size_t q = q0 + k;
            const int32_t i = scratch.point_lanes.path[q];
            for (int c = 0; c < 3; ++c) {
                scratch.org[3 * i + c] = next_org[3 * m + c] = oo[c][k];
                scratch.dir[3 * i + c] = next_dir[3 * m + c] = dd[c][k];
                scratch.prev_pos[3 * i + c] = pp[c][k];
            }
            scratch.prev_pdf[i] = pdf[q];
            scratch.next_active[m++] = i;
        }
    });
    scratch.next_active.resize(m);
}

// The numbers BSDF sampling draws at each point: two uniforms, and the lobe pick for the
// groups whose sampling reads it (every point's with all_picks: a guide picks too).
inline void draw_bsdf_numbers(const Wavefront& wavefront, int depth, bool all_picks) {
    PathScratch& scratch = wavefront.scratch;
    const size_t np = scratch.sorted.size();
    float* upick = grow(scratch.u_pick, np);
    float* u1 = grow(scratch.uniform_u, np);
    float* u2 = grow(scratch.uniform_v, np);
    if (all_picks)
        fill_uniforms(scratch, np, depth, kDimBsdfPick, upick);
    else
        for_material_groups(wavefront, [&](const Material& m, size_t a, size_t count) {
            if (sampling_picks(m)) fill_uniforms(scratch, a, count, depth, kDimBsdfPick, upick);
        });
    fill_uniforms(scratch, np, depth, kDimBsdfU, u1);
    fill_uniforms(scratch, np, depth, kDimBsdfV, u2);
    scratch.timer.lap(Stage::BsdfUniforms);
}

// Each point's next direction drawn by its material (N points of a material at a time), with
// its density and the BSDF's value there.
inline void sample_materials(const Wavefront& wavefront) {
    PathScratch& scratch = wavefront.scratch;
    const MaterialBuffers buffers = material_buffers(scratch);
    const float* upick = scratch.u_pick.data();
    const float* u1 = scratch.uniform_u.data();
    const float* u2 = scratch.uniform_v.data();
    for_material_groups(wavefront, [&](const Material& m, size_t a, size_t count) {
        const MaterialBuffers group = buffers.from(a);
        material_sample(m, group.view_local, group.eta, upick + a, u1 + a, u2 + a, group.light_local, group.pdf, count);
        material_eval(m, group.light_local, group.view_local, group.eta, group.bsdf_rgb, count);
    });
}

// The paths after their BSDF samples: throughput, Russian roulette, and the next bounce's ray
// for the survivors (scratch.next_active), while the path may still bounce.
inline void continue_paths(const Wavefront& wavefront, int depth) {
    PathScratch& scratch = wavefront.scratch;
    scratch.timer.lap(Stage::ShadeSample);
    scratch.next_active.clear();
    if (depth + 1 <= wavefront.settings.max_depth) update_paths(wavefront, depth, scratch.sorted.size());
    scratch.timer.lap(Stage::PathUpdate);
}

// BSDF sampling: each point's next direction from its material, and the paths that go on.
inline void sample_bsdf(const Wavefront& wavefront, int depth) {
    draw_bsdf_numbers(wavefront, depth, false);
    sample_materials(wavefront);
    continue_paths(wavefront, depth);
}

}  // namespace render_detail
PATINA_END_TARGET
