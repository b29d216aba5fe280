// The radiance cache's stages in the wavefront integrator (render/integrators/cache_impl.h calls them at
// the first hit; docs/radiance-cache.md), compiled once per width. Templates over the
// integrator's Wavefront, whose stages they sit between, and over its path tracer for the
// cache's own rays.
//   cache         add_cached_indirect: a hemisphere reconstructed (holes traced) per block
//                 of close first-hit points, integrated by each pixel against its BRDF N
//                 texels at a time; the path then only looks for emission at its next hit
//                 (the direct light's BRDF-sampling half). Glass, clear coats and every lobe
//                 narrower than two texels are left to the path tracer.
//   cache-guided  render/cache/guided_stages_impl.h: the cache points only, no reconstruction
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/constants.h"
#include "core/simd/kernel_width.h"
#include "core/vec3.h"
#include "render/cache/cache_regions.h"
#include "render/cache/error_criterion.h"
#include "render/cache/hemisphere.h"
#include "render/cache/radiance_cache_impl.h"
#include "render/cache/region_hemisphere.h"
#include "render/integrators/integrator.h"
#include "render/materials/material_impl.h"
#include "render/samplers/rng.h"
#include "render/scene.h"

PATINA_BEGIN_TARGET
namespace cache {
using namespace kernel_width;

// A texel's width in radians, about sqrt(2 pi) / R for an R x R hemisphere.
inline float texel_width(int resolution) { return 2.5066283f / static_cast<float>(resolution); }

// Whether a material's reflection is finer than the texels resolve: a clear coat or a lobe
// narrower than two texels. Looked up in the texture such a lobe sees a few texels -- a few
// path samples, shared by the pixel's samples and its neighbours -- where `path` averages one
// sample per camera sample: the lookup's error was many times path's (on the studio's
// car-paint ball 16x at 16 spp; on the room's glossy floor, a lobe of one to two texels, 1.8x
// path's at 16 spp, 32 BRDF samples looked up per pixel: docs/radiance-cache.md, "The room and
// the car"). Materials without a reflection lobe (glass, emitters) are neither fine nor
// resolved: the two tests below read this one from either side.
inline bool finer_than_texels(const Material& m, int resolution) {
    if (m.coat) return true;
    const std::optional<float> alpha = reflection_alpha(m);
    return alpha && *alpha < 2 * texel_width(resolution);
}

// Whether the material's lobes are wide enough to be integrated over the texels: a reflection
// lobe at least two texels wide, and no clear coat.
inline bool texel_resolvable(const Material& m, int resolution) {
    return reflection_alpha(m) && !finer_than_texels(m, resolution);
}

// Whether `cache` leaves a material's indirect light to the path tracer (the path goes on
// from the first hit as in `path`): glass and every reflection finer than the texels.
inline bool left_to_path(const Material& m, int resolution) { return transmits(m) || finer_than_texels(m, resolution); }

// Of the materials left to the path tracer, those whose first bounce the cache splits into
// paths of their own BRDF sampling (all but glass): the error of these pixels is the
// indirect light path's one sample per camera sample finds, while the cache makes the rest
// of the image cheap; splitting spends the samples where the error is. A clear coat or a
// near-mirror (narrower than half a texel) takes kSplitPaths (4 and 8 measured alike on the
// studio and the IES interior, 16 slower); a lobe between half a texel and two texels
// kBroadSplitPaths: on the room's floor, 30 % of its pixels, 1 / 2 / 4 paths gave
// biased_vs_path 2.65 / 2.55 / 2.14, the paths of a wider lobe reaching the whole room
// (docs/radiance-cache.md, "The room and the car").
constexpr int kSplitPaths = 4, kBroadSplitPaths = 1;
inline bool split_by_paths(const Material& m, int resolution) {
    return !transmits(m) && left_to_path(m, resolution);
}
inline size_t split_paths(const Material& m, int resolution) {
    const std::optional<float> alpha = reflection_alpha(m);
    return !m.coat && alpha && *alpha >= 0.5f * texel_width(resolution) ? kBroadSplitPaths : kSplitPaths;
}

// Whether the integrator's first-hit points of material m take their light from the cache's
// reconstruction: cache, all but those left to the path tracer; cache-guided, those whose
// guide the texels resolve.
inline bool served_by_cache(IntegratorMode mode, const Material& m, int resolution) {
    return mode == IntegratorMode::Cache ? !left_to_path(m, resolution) : texel_resolvable(m, resolution);
}

// Points share work at two levels when they have the same material, normals within
// kShareCos and the one within kSharePixels pixel footprints (at its distance from the
// camera) of the other's tangent plane (so a slanted wall's points share, a parallel
// surface behind does not):
//  - the samples of one pixel share a member: one integration of the reconstructed
//    radiance against the BRDF, for the view of the first (their direct light is sampled at
//    every one) -- on a Lambert surface, one per region hemisphere its samples draw;
//  - the pixels of a block of cache.block x cache.block share a query: one reconstructed
//    hemisphere (reprojection and holes), in the frame of its first point; each pixel
//    integrates it against its own BRDF and view (turned into that frame).
constexpr float kShareCos = 0.95f, kSharePixels = 2.0f;

inline bool shares_with(const Vec3f& rep_p, const Vec3f& rep_n, const ShadingPoint& sp, float footprint) {
    return dot(sp.n, rep_n) >= kShareCos && std::abs(dot(rep_n, sp.p - rep_p)) <= kSharePixels * footprint;
}
inline bool shares_with(const ShadingPoint& rep, const ShadingPoint& sp, float footprint) {
    return shares_with(rep.p, rep.n, sp, footprint);
}

// The pixel a camera sample lies in. Adaptive antialiasing traces pixel corners, and those on
// the image's right and bottom edges lie at x = width or y = height: they belong to the last
// column or row, not to a pixel beyond it (x = width would name the next row's first pixel).
struct SamplePixel {
    int64_t x, y;
};
inline SamplePixel pixel_of_sample(const Camera& cam, const CameraSample& c) {
    return {std::clamp<int64_t>(static_cast<int64_t>(std::floor(c.film_x)), 0, cam.width - 1),
            std::clamp<int64_t>(static_cast<int64_t>(std::floor(c.film_y)), 0, cam.height - 1)};
}

// The image region (cache_regions.h) of pixel (px, py): a member only takes a hemisphere its
// own pixel's region reconstructed, so which regions an item holds (its tile's size and
// place) does not change the image.
inline int32_t region_of_pixel(const Camera& cam, int64_t px, int64_t py) {
    const int64_t regions_x = (cam.width + kCacheRegionPixels - 1) / kCacheRegionPixels;
    return static_cast<int32_t>((py / kCacheRegionPixels) * regions_x + px / kCacheRegionPixels);
}

// The block of cache.block x cache.block pixels (image-aligned) of pixel (px, py).
inline int64_t block_of_pixel(const Camera& cam, int K, int64_t px, int64_t py) {
    const int64_t blocks_x = (cam.width + K - 1) / K;
    return (py / K) * blocks_x + px / K;
}

// The pre-pass pixel whose hemisphere pixel (px, py) tries first: a pixel drawn uniformly
// from the window of 2 x 2 blocks around it (kept inside the image; the item holds the
// regions the window reaches: RenderJob::cache_regions_near), by a number of the pixel's
// own for each pass. A pixel near a block's edge so takes the neighbouring block's
// hemisphere as often as the window overlaps that block -- a stochastic tent-weighted blend
// of the blocks' reconstructions: their noise, shared by a block, no longer steps at the
// block grid's lines (docs/radiance-cache.md, "The mosaic"), and progressive passes average
// the blend out. Two blocks wide rather than one: the studio's and the IES interior's
// mosaic measures (k = 16) went 1.28 -> 1.24 and 1.17 -> 1.10. Each attempt (below) draws
// numbers of its own.
template <class W>
inline int64_t jittered_pixel(const W& wavefront, int64_t px, int64_t py, uint32_t key, uint32_t attempt) {
    const Camera& cam = wavefront.scene.camera;
    const int K = 2 * wavefront.settings.cache.block;
    key = hash_u32(key ^ 0x5be0cd19u);  // not the numbers the sample's own rays draw
    auto draw = [&](int64_t p, uint32_t dim, int64_t lo, int64_t hi) {
        const int64_t q = p + static_cast<int64_t>(std::floor((uniform(key, dim) - 0.5f) * static_cast<float>(K) + 0.5f));
        return std::clamp<int64_t>(q, lo, hi - 1);
    };
    return draw(py, 2 * attempt + 1, 0, cam.height) * cam.width + draw(px, 2 * attempt, 0, cam.width);
}

// Jittered pixels a sample draws until one's hemisphere shares its surface within its reach.
// One draw fell back to the pixel's own hemisphere wherever the window reached past a reach
// (corners, the IES interior's short reaches), which put the block grid back into the image:
// with a draw a sample on every surface the IES interior's mosaic measure (16 spp, k = 4 / 8
// / 16) was 1.07 / 1.16 / 1.11 with one draw, 1.00 / 1.02 / 0.97 with four
// (docs/radiance-cache.md, "The mosaic").
constexpr uint32_t kJitterAttempts = 4;

// The hemisphere a region reconstructed for point sp of pixel (px, py), as an index in
// stored.in_use (added there at first use), or -1: the one the first of kJitterAttempts
// jittered pixels' pre-pass points took whose surface sp shares within its reach, else the
// one the pixel's own pre-pass point took if sp shares its surface (the sample lies within a
// pixel of that point), else the first of its block and region sharing sp's surface with sp
// within its reach.
template <class W>
inline int32_t stored_hemisphere(const W& wavefront, CacheState& cache, const ShadingPoint& sp, int64_t px, int64_t py,
                                 float footprint, uint32_t key) {
    StoredHemispheres& stored = cache.stored;
    const std::vector<const RegionHemisphere*>& kept = wavefront.scratch.cache_shared_hemispheres;
    auto take = [&](int32_t i) {
        if (stored.slot[i] < 0) {
            stored.slot[i] = static_cast<int32_t>(stored.in_use.size());
            stored.in_use.push_back(kept[i]);
        }
        return stored.slot[i];
    };
    auto shares = [&](const RegionHemisphere& h) {
        return h.material == static_cast<int32_t>(sp.material) && shares_with(h.p, h.n, sp, footprint);
    };
    auto within_reach = [&](const RegionHemisphere& h) { return dot(sp.p - h.p, sp.p - h.p) <= h.reach * h.reach; };
    for (uint32_t attempt = 0; attempt < kJitterAttempts; ++attempt) {
        const auto near = stored.by_pixel.find(jittered_pixel(wavefront, px, py, key, attempt));
        if (near != stored.by_pixel.end() && shares(*kept[near->second]) && within_reach(*kept[near->second]))
            return take(near->second);
    }
    const auto own = stored.by_pixel.find(py * wavefront.scene.camera.width + px);
    if (own != stored.by_pixel.end() && shares(*kept[own->second])) return take(own->second);
    const int block = wavefront.settings.cache.block;
    const auto found = stored.by_block.find(block_of_pixel(wavefront.scene.camera, block, px, py));
    if (found == stored.by_block.end()) return -1;
    const int32_t region = region_of_pixel(wavefront.scene.camera, px, py);
    for (const int32_t i : found->second)
        if (kept[i]->region == region && shares(*kept[i]) && within_reach(*kept[i])) return take(i);
    return -1;
}

// Whether a reconstructed hemisphere's integral against the material is the same for every
// view: its members (add_cached_indirect) share one integration.
inline bool integral_ignores_view(const Material& m) { return m.is<Lambert>() && !m.coat; }

// The key of the member that a sample of `pixel` taking the region's hemisphere h
// (stored.in_use, -1: none; fewer than `hemispheres`) joins: a pixel's samples share a member
// per hemisphere they draw.
inline int64_t pixel_member_key(int64_t pixel, int32_t h, size_t hemispheres) {
    return pixel * (static_cast<int64_t>(hemispheres) + 1) + (h + 1);
}

// The first-hit points the cache serves, as queries and members (CacheState); returns the
// number of queries. With `stored`, a member takes the hemisphere its region reconstructed
// where there is one (stored_hemisphere) and makes or joins a query only where there is not.
template <class W, class Accept>
inline size_t collect_queries(const W& wavefront, CacheState& cache, Accept accept, bool stored) {
    QueryTable& table = cache.table;
    StoredHemispheres& hemispheres = cache.stored;
    const PathScratch& scratch = wavefront.scratch;
    const size_t np = scratch.sorted.size();
    const Camera& cam = wavefront.scene.camera;
    const int K = wavefront.settings.cache.block;
    hemispheres.by_block.clear();
    hemispheres.by_pixel.clear();
    hemispheres.in_use.clear();
    hemispheres.slot.assign(stored ? scratch.cache_shared_hemispheres.size() : 0, -1);
    if (stored)
        for (size_t i = 0; i < scratch.cache_shared_hemispheres.size(); ++i) {
            const RegionHemisphere& h = *scratch.cache_shared_hemispheres[i];
            hemispheres.by_block[h.block].push_back(static_cast<int32_t>(i));
            for (const int64_t pixel : h.pixels) hemispheres.by_pixel[pixel] = static_cast<int32_t>(i);
        }
    table.queries.clear();
    table.query_point.clear();
    table.member_point.clear();
    table.member_query.clear();
    table.member_own.clear();
    table.member_of_point.assign(np, -1);
    for (size_t k = 0; k < wavefront.scene.materials.size(); ++k) {
        if (!accept(wavefront.scene.materials[k])) continue;
        table.pixel_member.clear();  // per material
        table.block_queries.clear();
        // each sample its own draw where a hemisphere's integral serves all its members (a
        // pixel's samples then average the window's blend instead of taking one draw of it),
        // one a pixel where each member integrates (a draw a sample cost the IES interior's
        // table floor 40 % more time)
        const bool draw_each = !hemispheres.by_block.empty() && integral_ignores_view(wavefront.scene.materials[k]);
        const size_t first = scratch.material_start[k], last = scratch.material_start[k + 1];
        for (size_t q = first; q < last; ++q) {
            const ShadingPoint& sp = scratch.sorted[q];
            const auto [px, py] = pixel_of_sample(cam, wavefront.camera_samples[sp.path]);
            const int64_t pixel = py * cam.width + px;
            const float footprint =
                wavefront.results[sp.path].depth * 2.0f * cam.tan_half_fov / static_cast<float>(cam.height);
            // the sample's own key (the stream key is the pixel's, shared by its samples)
            const uint32_t key =
                sample_key(static_cast<uint32_t>(scratch.point_keys[q]), static_cast<uint32_t>(scratch.point_index[q]));
            // the region's hemisphere this sample draws where each sample draws its own
            // (draw_each), else the one the pixel's first member drew (below)
            int32_t h = draw_each ? stored_hemisphere(wavefront, cache, sp, px, py, footprint, key) : -1;
            const int64_t member_key = pixel_member_key(pixel, h, scratch.cache_shared_hemispheres.size());
            auto found = table.pixel_member.find(member_key);
            if (found != table.pixel_member.end() &&
                shares_with(scratch.sorted[table.member_point[found->second]], sp, footprint)) {
                table.member_of_point[q] = found->second;
                continue;
            }
            if (!draw_each && !hemispheres.by_block.empty())
                h = stored_hemisphere(wavefront, cache, sp, px, py, footprint, key);
            // a new member: of a region's hemisphere, of a query of its block, or of a new one
            std::vector<int32_t>& block = table.block_queries[block_of_pixel(cam, K, px, py)];
            const float min_radius = kMinReusePixels * footprint / wavefront.settings.cache.error;
            const Query own{sp.p, sp.ng, sp.t, sp.b, sp.n, key, min_radius};
            int32_t query = h >= 0 ? -1 - h : -1;
            for (size_t i = 0; i < block.size() && h < 0 && query < 0; ++i)
                if (shares_with(scratch.sorted[table.query_point[block[i]]], sp, footprint)) query = block[i];
            if (h < 0 && query < 0) {
                query = static_cast<int32_t>(table.queries.size());
                table.queries.push_back(own);
                table.query_point.push_back(static_cast<int32_t>(q));
                block.push_back(query);
            }
            const int32_t member = static_cast<int32_t>(table.member_point.size());
            table.member_own.push_back(own);
            table.member_point.push_back(static_cast<int32_t>(q));
            table.member_query.push_back(query);
            table.member_of_point[q] = member;
            if (found == table.pixel_member.end()) table.pixel_member.emplace(member_key, member);
        }
    }
    index_members(cache);
    return table.queries.size();
}

// A member's view direction in its query's frame, or its region hemisphere's (the frames of
// the two points of a share are within acos kShareCos; a view that would fall under that
// horizon keeps its own).
inline void view_in_query_frame(const PathScratch& scratch, const CacheState& cache, int32_t member, float* v) {
    const QueryTable& table = cache.table;
    const int32_t q = table.member_point[member], u = table.member_query[member];
    const float* own = scratch.v_local.data() + 3 * q;
    std::copy(own, own + 3, v);
    if (u >= 0 && q == table.query_point[u]) return;
    const ShadingPoint& a = scratch.sorted[q];
    Vec3f t, b, n;
    if (u >= 0) {
        const ShadingPoint& r = scratch.sorted[table.query_point[u]];
        t = r.t, b = r.b, n = r.n;
    } else {
        const RegionHemisphere& h = *cache.stored.in_use[-1 - u];
        t = h.t, b = h.b, n = h.n;
    }
    const Vec3f world = own[0] * a.t + own[1] * a.b + own[2] * a.n;
    const float z = dot(world, n);
    if (!(z > 0.01f)) return;
    v[0] = dot(world, t), v[1] = dot(world, b), v[2] = z;
}

// f(l_t, v) at the texels [0, n) listed in integration.lit_directions for the point's view v
// (integration.bsdf_values, RGB).
inline void eval_at_texels(const Material& m, const float* v, float eta, CacheState& cache, size_t n) {
    HemisphereIntegration& integration = cache.integration;
    float* vv = grow(integration.views, 3 * n);
    float* ee = grow(integration.etas, n);
    for (size_t k = 0; k < n; ++k) std::copy(v, v + 3, vv + 3 * k), ee[k] = eta;
    render_detail::material_eval(m, integration.lit_directions.data(), vv, ee, grow(integration.bsdf_values, 3 * n), n);
}

template <class W>
inline void add_counts(const W& wavefront, const CacheCounts& c, const CacheState& cache, size_t rays_before) {
    wavefront.scratch.cache_points += c.points;
    wavefront.scratch.cache_queries += c.queries;
    wavefront.scratch.cache_texels_reprojected += c.reprojected + c.from_misses;
    wavefront.scratch.cache_texels_traced += c.traced;
    wavefront.scratch.rays_traced += cache.inner.rays_traced - rays_before;
}

// `cache`: the materials whose texel hits take cache.hit_paths paths (split_glossy_hits): those
// whose lobes the texels do not resolve (glass, coats, narrow lobes: what sends a cache point
// the sun in a glossy reflection). None for cache-guided, whose guides need the light's shape,
// and for the same reason only `cache` refines a point's concentrated texels.
inline void mark_split_materials(const std::vector<Material>& materials, const IntegratorSettings& settings,
                                 CacheState& cache) {
    cache.texel_refinement.enabled = settings.mode == IntegratorMode::Cache;
    GlossyHitSplit& split = cache.glossy_split;
    split.split_material.clear();
    split.hit_paths = settings.cache.hit_paths;
    if (settings.mode != IntegratorMode::Cache || split.hit_paths < 2) return;
    for (const Material& m : materials)
        split.split_material.push_back(!m.is<Emitter>() && !texel_resolvable(m, settings.cache.resolution));
}

// The start of either integrator's cache stage: the worker's cache state, timed by its
// timer, holding the batch's queries and members of the materials the cache serves, the
// shared points of the item's regions to start from, and the texel directions.
template <class W>
inline CacheState& start_cache_stage(const W& wavefront) {
    CacheState& cache = cache_state(wavefront.scratch);
    cache.timer = &wavefront.scratch.timer;
    const int R = wavefront.settings.cache.resolution;
    collect_queries(wavefront, cache, [&](const Material& m) { return served_by_cache(wavefront.settings.mode, m, R); },
                    wavefront.settings.mode == IntegratorMode::Cache);
    cache.build.shared = &wavefront.scratch.cache_shared;
    cache.texel_directions.prepare(R);
    mark_split_materials(wavefront.scene.materials, wavefront.settings, cache);
    return cache;
}

// The stream key of the split paths of sorted first-hit point q.
inline uint32_t split_key(const PathScratch& scratch, size_t q) {
    return hash_u32(sample_key(static_cast<uint32_t>(scratch.point_keys[q]), static_cast<uint32_t>(scratch.point_index[q])) ^
                    0x3c6ef372u);
}

// The K BRDF samples of each sorted first-hit point of material m in [first, last), direction
// (lobe_directions), density (pdfs) and value (bsdf_values) of sample j of point q at
// (q - first) K + j: the material's kernels run once over all of them. One call per point ran
// K of N lanes, on the room's floor (K = 1) one: sampling and evaluation were 34 % of the split
// stage's time at width 16 (docs/radiance-cache.md, "The cache's own stages cheaper").
inline void sample_split_lobes(const PathScratch& scratch, const Material& m, size_t first, size_t last, size_t K,
                               HemisphereIntegration& integration) {
    const size_t n = (last - first) * K;
    float* vv = grow(integration.views, 3 * n);
    float* ee = grow(integration.etas, n);
    float* u0 = grow(integration.u_pick, n);
    float* u1 = grow(integration.uniform_u, n);
    float* u2 = grow(integration.uniform_v, n);
    for (size_t q = first; q < last; ++q) {
        const uint32_t key = split_key(scratch, q);
        for (size_t j = 0; j < K; ++j) {
            const size_t s = (q - first) * K + j;
            std::copy(scratch.v_local.data() + 3 * q, scratch.v_local.data() + 3 * q + 3, vv + 3 * s);
            ee[s] = scratch.eta[q];
            u0[s] = uniform(key, 3 * static_cast<uint32_t>(j));
            u1[s] = uniform(key, 3 * static_cast<uint32_t>(j) + 1);
            u2[s] = uniform(key, 3 * static_cast<uint32_t>(j) + 2);
        }
    }
    float* l = grow(integration.lobe_directions, 3 * n);
    render_detail::material_sample(m, vv, ee, u0, u1, u2, l, grow(integration.pdfs, n), n);
    render_detail::material_eval(m, l, vv, ee, grow(integration.bsdf_values, 3 * n), n);
}

// cache: the first-hit points of split_by_paths materials, each its indirect light from
// split_paths paths along its BRDF's own samples (traced by the path tracer as the cache's
// rays are: the emission they see directly is the direct light's, left to the outer path's
// next hit with its MIS weight). An unbiased estimate: path's with its first bounce split.
template <class W, class Tracer>
inline void split_narrow_lobes(const W& wavefront, Tracer& trace) {
    PathScratch& scratch = wavefront.scratch;
    CacheState& cache = cache_state(scratch);
    HemisphereIntegration& integration = cache.integration;
    CachePointBuild& build = cache.build;
    const int R = wavefront.settings.cache.resolution;
    build.rays.clear();
    integration.split_weights.clear();
    const size_t rays_before = cache.inner.rays_traced;
    for (size_t k = 0; k < wavefront.scene.materials.size(); ++k) {
        const Material& m = wavefront.scene.materials[k];
        if (!split_by_paths(m, R)) continue;
        const size_t K = split_paths(m, R);
        const size_t first = scratch.material_start[k], last = scratch.material_start[k + 1];
        sample_split_lobes(scratch, m, first, last, K, integration);
        for (size_t q = first; q < last; ++q) {
            const ShadingPoint& sp = scratch.sorted[q];
            const uint32_t key = split_key(scratch, q);
            const Vec3f o = sp.p + wavefront.ray_offset * sp.ng;
            for (size_t j = 0; j < K; ++j) {
                const size_t s = (q - first) * K + j;
                const float* d = integration.lobe_directions.data() + 3 * s;
                const float pdf = integration.pdfs[s];
                if (!(pdf > 0) || !(d[2] > 0)) continue;
                const Vec3f wd = normalize(d[0] * sp.t + d[1] * sp.b + d[2] * sp.n);
                if (!(dot(wd, sp.ng) > 0)) continue;
                const float weight = d[2] / (pdf * static_cast<float>(K));
                for (int c = 0; c < 3; ++c) integration.split_weights.push_back(integration.bsdf_values[3 * s + c] * weight);
                build.rays.push(o, wd, key, static_cast<uint32_t>(j), static_cast<int32_t>(q));
            }
            scratch.cached[sp.path] = 1;
        }
    }
    if (build.rays.size() == 0) return;
    trace_queue(cache, trace);
    for (size_t r = 0; r < build.rays.size(); ++r) {
        const int32_t path = scratch.sorted[build.rays.where[r]].path;
        const float* Tp = scratch.throughput.data() + 3 * path;
        for (int c = 0; c < 3; ++c)
            wavefront.results[path].rgb[c] += Tp[c] * integration.split_weights[3 * r + c] * build.results[r].rgb[c];
    }
    wavefront.scratch.rays_traced += cache.inner.rays_traced - rays_before;
    cache.lap(Stage::CacheSplit);
}

// cache: the indirect light of every first-hit point but those left to the path tracer
// (left_to_path), from the cache.
template <class W, class Tracer>
inline void add_cached_indirect(const W& wavefront, Tracer& trace) {
    PathScratch& scratch = wavefront.scratch;
    CacheState& cache = start_cache_stage(wavefront);
    HemisphereIntegration& integration = cache.integration;
    QueryTable& table = cache.table;
    const CacheSettings& cfg = wavefront.settings.cache;
    const int R = cfg.resolution;
    const size_t texel_count = static_cast<size_t>(R) * R;
    const float texel = texel_solid_angle(R);
    const size_t rays_before = cache.inner.rays_traced;
    // one member's indirect light from its query's radiance; the texels with light (count of
    // them in integration.lit_directions and lit_radiance) listed once for all the query's members
    auto integrate = [&](int32_t member, size_t count) {
        const size_t q = table.member_point[member];
        const ShadingPoint& sp = scratch.sorted[q];
        const Material& m = wavefront.scene.materials[sp.material];
        float v[3];
        view_in_query_frame(scratch, cache, member, v);
        double sum[3] = {0, 0, 0};
        if (texel_resolvable(m, R)) {
            // the texels with light, N at a time through the BRDF
            const float* l = integration.lit_directions.data();
            const float* rgb = integration.lit_radiance.data();
            if (count > 0) {
                eval_at_texels(m, v, scratch.eta[q], cache, count);
                const float* f = integration.bsdf_values.data();  // grown by eval_at_texels
                for (size_t k = 0; k < count; ++k)
                    for (int c = 0; c < 3; ++c)
                        sum[c] += static_cast<double>(f[3 * k + c]) * rgb[3 * k + c] * l[3 * k + 2];
            }
            for (double& s : sum) s *= texel;
        }  // else an emitter: it reflects nothing (the lobes the texels cannot resolve are left_to_path)
        for (int c = 0; c < 3; ++c) integration.member_light[3 * member + c] = static_cast<float>(sum[c]);
    };
    const TexelDirections& directions = cache.texel_directions;
    // the members [begin, end) of one hemisphere (a query's or a region's)
    auto consume_members = [&](const int32_t* begin, const int32_t* end, const float* radiance) {
        float* l = grow(integration.lit_directions, 3 * texel_count);
        float* rgb = grow(integration.lit_radiance, 3 * texel_count);
        size_t count = 0;
        for (size_t t = 0; t < texel_count; ++t) {
            const float* L = radiance + 3 * t;
            if (!(L[0] > 0 || L[1] > 0 || L[2] > 0)) continue;
            l[3 * count] = directions.x[t], l[3 * count + 1] = directions.y[t], l[3 * count + 2] = directions.z[t];
            std::copy(L, L + 3, rgb + 3 * count);
            ++count;
        }
        int32_t lambert = -1;  // the query's last Lambert member: its integral does not depend on the view
        for (const int32_t* i = begin; i < end; ++i) {
            const int32_t member = *i;
            const ShadingPoint& sp = scratch.sorted[table.member_point[member]];
            const Material& m = wavefront.scene.materials[sp.material];
            const bool plain = integral_ignores_view(m);
            if (plain && lambert >= 0 && scratch.sorted[table.member_point[lambert]].material == sp.material) {
                const auto from = integration.member_light.begin() + 3 * lambert;
                std::copy(from, from + 3, integration.member_light.begin() + 3 * member);
                continue;
            }
            integrate(member, count);
            if (plain) lambert = member;
        }
    };
    auto consume = [&](size_t qi, const float* radiance) {
        const int32_t* m = table.query_members.data();
        consume_members(m + table.query_first[qi], m + table.query_first[qi + 1], radiance);
    };
    integration.member_light.assign(3 * table.member_point.size(), 0.0f);
    CacheCounts c = reconstruct_hemispheres(cfg, wavefront.ray_offset, true, cache, trace, consume);
    // the members of the regions' hemispheres
    const StoredHemispheres& stored = cache.stored;
    for (size_t s = 0; s < stored.in_use.size(); ++s) {
        const int32_t* m = stored.members.data();
        consume_members(m + stored.first[s], m + stored.first[s + 1], stored.in_use[s]->radiance.data());
    }
    c.queries += stored.in_use.size();
    cache.lap(Stage::CacheIntegrate);
    add_counts(wavefront, c, cache, rays_before);
    // every point of a member: its indirect light
    for (size_t q = 0; q < scratch.sorted.size(); ++q) {
        if (table.member_of_point[q] < 0) continue;
        const int32_t path = scratch.sorted[q].path;
        const float* Tp = scratch.throughput.data() + 3 * path;
        const float* light = integration.member_light.data() + 3 * table.member_of_point[q];
        for (int k = 0; k < 3; ++k) wavefront.results[path].rgb[k] += Tp[k] * light[k];
        scratch.cached[path] = 1;
    }
    split_narrow_lobes(wavefront, trace);
}

// The cache points of an image region (render/cache/cache_regions.h) from its pre-pass's
// first-hit points (scratch.sorted: one a pixel, generation 0 at its centre): the queries a work item would
// make of them (collect_queries: a block's close points of the materials the cache serves
// share one) are placed in rounds as an item's are (with no shared points to start from),
// built, and moved to `out` without their build-only data.
// For `cache` the queries' hemispheres are reconstructed too (holes traced, the second cache
// point's lookups: what an item does) and kept in `hemispheres` (region_hemisphere.h) for the
// members of the generation's items that would make the same query; members whose samples
// miss every pre-pass query (edges, curved surfaces) make their own.
template <class W, class Tracer>
inline void build_region_points(const W& wavefront, Tracer& trace, std::vector<CachePoint>& out,
                                std::vector<RegionHemisphere>& hemispheres) {
    PathScratch& scratch = wavefront.scratch;
    CacheState& cache = cache_state(scratch);
    cache.timer = &scratch.timer;
    QueryTable& table = cache.table;
    CachePointBuild& build = cache.build;
    const CacheSettings& cfg = wavefront.settings.cache;
    const auto served = [&](const Material& m) { return served_by_cache(wavefront.settings.mode, m, cfg.resolution); };
    collect_queries(wavefront, cache, served, false);
    build.shared = nullptr;
    mark_split_materials(wavefront.scene.materials, wavefront.settings, cache);
    const size_t rays_before = cache.inner.rays_traced;
    hemispheres.clear();
    if (wavefront.settings.mode == IntegratorMode::Cache) {
        const Camera& cam = wavefront.scene.camera;
        const size_t texel_count = static_cast<size_t>(cfg.resolution) * cfg.resolution;
        auto keep = [&](size_t qi, const float* radiance) {
            const ShadingPoint& sp = scratch.sorted[table.query_point[qi]];
            const auto [px, py] = pixel_of_sample(cam, wavefront.camera_samples[sp.path]);
            RegionHemisphere h;
            h.block = block_of_pixel(cam, cfg.block, px, py);
            h.region = region_of_pixel(cam, px, py);
            h.material = static_cast<int32_t>(sp.material);
            h.p = sp.p, h.n = sp.n, h.t = sp.t, h.b = sp.b;
            h.reach = kShareError * build.pool[build.assigned[qi]]->reuse_radius;
            h.radiance.assign(radiance, radiance + 3 * texel_count);
            hemispheres.push_back(std::move(h));
        };
        const CacheCounts c = reconstruct_hemispheres(cfg, wavefront.ray_offset, true, cache, trace, keep);
        // (consumed in order: hemisphere u is query u) each pre-pass pixel's
        for (size_t m = 0; m < table.member_point.size(); ++m) {
            const int32_t path = scratch.sorted[table.member_point[m]].path;
            const auto [px, py] = pixel_of_sample(cam, wavefront.camera_samples[path]);
            hemispheres[table.member_query[m]].pixels.push_back(py * cam.width + px);
        }
        scratch.cache_texels_reprojected += c.reprojected + c.from_misses;
        scratch.cache_texels_traced += c.traced;
    } else {
        place_cache_points(cfg, wavefront.ray_offset, table.queries.data(), table.queries.size(), cache, trace);
    }
    out.clear();
    for (size_t a = 0; a < build.used; ++a) {
        out.push_back(std::move(build.points[a]));
        drop_build_data(out.back());
    }
    scratch.cache_points += build.used;
    scratch.rays_traced += cache.inner.rays_traced - rays_before;
}

}  // namespace cache
PATINA_END_TARGET
