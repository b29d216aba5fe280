// The radiance cache at work on one batch of shading points (docs/radiance-cache.md),
// compiled once per width (included by render/integrators/kernels_impl.h). The batch is one (tile, pass)
// work item's camera samples; the cache points it starts from are those of the image
// regions its tile overlaps (render/cache/cache_regions.h: built by a pre-pass of their
// own, read only), and the points it builds itself live for the call, so the image
// depends on the seed only.
//   1. placement, in rounds: each point takes the existing cache point (a region's or one
//      built here) of least error
//      (render/cache/error_criterion.h) if that is within the bound; the others, in order,
//      become new cache points unless a new one of this round already lies within the bound
//      (with the radius of those built so far as the estimate), and the round's new ones are
//      built together;
//   2. building: R^2 rays over the point's hemisphere (one per texel, jittered), traced as one
//      wavefront by the path tracer with the emission seen directly left out: each texel is
//      one sample of the indirect incident radiance; then layers and surfels (surfels.h);
//   3. every other point gets its hemisphere by reprojection (reprojection_impl.h) and, where
//      that leaves holes, by tracing them from the point, all the holes of a chunk of points
//      in one wavefront (or, for guiding, which needs no exact value, the mean of the rest).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/simd/kernel_width.h"
#include "core/vec3.h"
#include "render/cache/bit_mask.h"
#include "render/cache/cache_point.h"
#include "render/cache/cache_settings.h"
#include "render/cache/cache_state_impl.h"
#include "render/cache/concentrated_texels.h"
#include "render/cache/error_criterion.h"
#include "render/cache/hemisphere.h"
#include "render/cache/reprojection_impl.h"
#include "render/cache/surfels.h"
#include "render/cache/texel_outliers.h"
#include "render/integrators/integrator.h"
#include "render/integrators/stage_timer.h"
#include "render/samplers/rng.h"

PATINA_BEGIN_TARGET
namespace cache {

constexpr int kMaxRounds = 6;
constexpr size_t kChunk = 32;        // points reprojected, hole-traced and consumed together
constexpr size_t kMaxWavefront = 16384;  // rays per call of the path tracer

inline uint32_t cache_point_key(uint32_t point_key) { return hash_u32(point_key ^ 0x5bd1e995u); }
inline uint32_t hole_key(uint32_t point_key) { return hash_u32(point_key ^ 0x68e31da4u); }

// The stream key of a texel's further path s from its hit (split_glossy_hits): path 0 is the
// texel's own (the hemisphere's key), each further one a stream of its own, the texel its index.
inline uint32_t split_path_key(uint32_t key, int s) {
    return s == 0 ? key : hash_u32(key ^ (0x9e3779b9u * static_cast<uint32_t>(s)));
}

// The world direction of a jittered sample in texel t of the hemisphere of q.
inline Vec3f jittered_direction(const Query& q, int R, int32_t t, uint32_t key) {
    const float u = (static_cast<float>(t % R) + uniform(key, 2u * t)) / R;
    const float v = (static_cast<float>(t / R) + uniform(key, 2u * t + 1)) / R;
    float x, y, z;
    square_to_hemisphere(u, v, x, y, z);
    return normalize(x * q.t + y * q.b + z * q.n);
}

// Traces the queue in wavefronts of at most kMaxWavefront rays; results in build.results.
template <class Tracer>
inline void trace_queue(CacheState& cache, Tracer& trace) {
    CachePointBuild& build = cache.build;
    const size_t n = build.rays.size();
    build.results.resize(n);
    for (size_t a = 0; a < n; a += kMaxWavefront) {
        const size_t m = std::min(kMaxWavefront, n - a);
        trace(build.rays.org.data() + 3 * a, build.rays.dir.data() + 3 * a, build.rays.keys.data() + a,
              build.rays.indices.data() + a, m, build.results.data() + a);
    }
}

// The texels `texels` (by `where`), each with its first path's radiance, take the further paths
// `further` (traced here through build's queue and results, which keep the caller's rays) and
// hold the mean of their `paths` paths in all. texel(where): the texel's radiance (RGB).
template <class Tracer, class Texel>
inline void hold_mean_of_further_paths(CacheState& cache, Tracer& trace, RayQueue& further,
                                       const std::vector<int32_t>& texels, int paths, Texel texel) {
    CachePointBuild& build = cache.build;
    std::swap(build.rays, further);
    trace_queue(cache, trace);
    for (size_t r = 0; r < build.rays.size(); ++r) {
        float* L = texel(build.rays.where[r]);
        for (int c = 0; c < 3; ++c) L[c] += build.results[r].rgb[c];
    }
    const float share = 1.0f / static_cast<float>(paths);
    for (const int32_t where : texels) {
        float* L = texel(where);
        for (int c = 0; c < 3; ++c) L[c] *= share;
    }
    std::swap(build.rays, further);
}

// The texels just traced (build.rays, build.results) whose first hit is on a glossy material
// (split.split_material) take split.hit_paths paths from that hit -- the texel's ray traced again
// with streams of their own -- and the mean of them: unbiased (every path is one sample of the
// light leaving the same hit towards A), and the light such a hit sends A is where a cache
// point's heavy tail is (docs/radiance-cache.md, "Bias"): the sun in the glossy lobe, caught
// by one light or BRDF sample of the texel's one path, shared by every point reusing A.
// texel(where) is the radiance (RGB) of the texel of a ray's `where`, its first path's in it.
template <class Tracer, class Texel>
inline void split_glossy_hits(CacheState& cache, Tracer& trace, Texel texel) {
    CachePointBuild& build = cache.build;
    GlossyHitSplit& split = cache.glossy_split;
    const int K = split.hit_paths;
    if (K < 2 || split.split_material.empty()) return;
    split.rays.clear();
    split.texels.clear();
    for (size_t r = 0; r < build.rays.size(); ++r) {
        const int32_t m = build.results[r].material;
        if (m < 0 || static_cast<size_t>(m) >= split.split_material.size() || !split.split_material[m]) continue;
        const Vec3f o = load_vec3(build.rays.org.data() + 3 * r), d = load_vec3(build.rays.dir.data() + 3 * r);
        for (int s = 1; s < K; ++s)
            split.rays.push(o, d, split_path_key(build.rays.keys[r], s), build.rays.indices[r], build.rays.where[r]);
        split.texels.push_back(build.rays.where[r]);
    }
    if (split.texels.empty()) return;
    hold_mean_of_further_paths(cache, trace, split.rays, split.texels, K, texel);
}

// The texels of a chunk's new points whose light sits in a few texels (concentrated_texels.h)
// take kStrata further paths each, stratified within the texel, and hold the mean of all their
// paths (their hits, for the surfels, stay the first path's). points: the chunk's `count`
// points, of the queries pending[0 .. count); texel(where) as split_glossy_hits's.
template <class Tracer, class Texel>
inline void refine_concentrated_texels(CacheState& cache, Tracer& trace, CachePoint* points, size_t count,
                                       const Query* queries, const int32_t* pending, float eps, Texel texel) {
    TexelRefinement& refinement = cache.texel_refinement;
    if (!refinement.enabled || count == 0) return;
    const int R = points[0].resolution;
    const size_t texel_count = static_cast<size_t>(R) * R;
    refinement.rays.clear();
    refinement.texels.clear();
    for (size_t k = 0; k < count; ++k) {
        const CachePoint& a = points[k];
        refinement.selected.clear();
        select_texels_to_refine(a.radiance.data(), R, refinement, refinement.selected);
        const uint32_t key = cache_point_key(queries[pending[k]].key);
        const Vec3f o = a.p + eps * a.ng;
        for (const int32_t t : refinement.selected) {
            if (a.kind[t] == kTexelBelow) continue;  // it holds no light
            const int32_t where = static_cast<int32_t>(k * texel_count) + t;
            refinement.texels.push_back(where);
            push_strata(a, t, key, o, where, refinement.rays);
        }
    }
    if (refinement.rays.size() == 0) return;
    // a stratum under the surface takes no path and counts as no light
    hold_mean_of_further_paths(cache, trace, refinement.rays, refinement.texels, 1 + kStrata, texel);
}

// Builds cache points at the queries build.pending (appended to build.points), tracing the
// hemispheres of kChunk of them together: the ray queue and its results stay bounded however
// many points a region needs (at --cache-error 0.01 and --cache-block 1 a region's hundreds of
// points in one queue were its largest allocation; docs/radiance-cache.md). Each ray's numbers
// are its own key's, so the points are the same bits whatever the chunk.
template <class Tracer>
inline void build_cache_points(const CacheSettings& cfg, float eps, const Query* queries, CacheState& cache,
                               Tracer& trace) {
    CachePointBuild& build = cache.build;
    const int R = cfg.resolution;
    const size_t texel_count = static_cast<size_t>(R) * R;
    const size_t first = build.used;
    if (build.points.size() < first + build.pending.size()) build.points.resize(first + build.pending.size());
    for (size_t chunk_begin = 0; chunk_begin < build.pending.size(); chunk_begin += kChunk) {
        const size_t chunk_end = std::min(build.pending.size(), chunk_begin + kChunk);
        CachePoint* chunk = build.points.data() + first + chunk_begin;
        build.rays.clear();
        for (size_t k = chunk_begin; k < chunk_end; ++k) {
            const Query& q = queries[build.pending[k]];
            CachePoint& a = chunk[k - chunk_begin];
            a.p = q.p, a.ng = q.ng, a.t = q.t, a.b = q.b, a.n = q.n;
            a.resolution = R;
            a.radiance.assign(3 * texel_count, 0.0f);
            a.dist.assign(texel_count, INFINITY);
            a.kind.assign(texel_count, kTexelBelow);
            a.hit_point.assign(3 * texel_count, 0.0f);
            a.hit_normal.assign(3 * texel_count, 0.0f);
            const uint32_t key = cache_point_key(q.key);
            const Vec3f o = q.p + eps * q.ng;
            for (size_t t = 0; t < texel_count; ++t) {
                const Vec3f d = jittered_direction(q, R, static_cast<int32_t>(t), key);
                if (!(dot(d, q.ng) > 0)) continue;  // under the geometric surface: no light from there
                const int32_t where = static_cast<int32_t>((k - chunk_begin) * texel_count + t);
                build.rays.push(o, d, key, static_cast<uint32_t>(t), where);
            }
        }
        cache.lap(Stage::CachePlace);
        trace_queue(cache, trace);
        cache.lap(Stage::CacheBuild);
        for (size_t r = 0; r < build.rays.size(); ++r) {
            const size_t k = build.rays.where[r] / texel_count, t = build.rays.where[r] % texel_count;
            CachePoint& a = chunk[k];
            const PathResult& res = build.results[r];
            std::copy(res.rgb, res.rgb + 3, a.radiance.data() + 3 * t);
            if (!(res.depth < INFINITY)) {
                a.kind[t] = kTexelMiss;
                continue;
            }
            const Vec3f d = load_vec3(build.rays.dir.data() + 3 * r);
            a.kind[t] = kTexelHit;
            a.dist[t] = res.depth;
            store_vec3(a.p + res.depth * d, a.hit_point.data() + 3 * t);
            Vec3f m = load_vec3(res.normal);
            // lights and backs of one-sided surfaces leave no normal: a surfel facing A
            if (!(dot(m, m) > 0.5f) || dot(m, d) > 0) m = -d;
            store_vec3(m, a.hit_normal.data() + 3 * t);
        }
        const auto texel = [&](int32_t where) {
            return chunk[where / texel_count].radiance.data() + 3 * (where % texel_count);
        };
        split_glossy_hits(cache, trace, texel);
        refine_concentrated_texels(cache, trace, chunk, chunk_end - chunk_begin, queries,
                                   build.pending.data() + chunk_begin, eps, texel);
        for (size_t k = chunk_begin; k < chunk_end; ++k)
            bound_isolated_texels(chunk[k - chunk_begin].radiance.data(), R, build.luminances);
        cache.lap(Stage::CacheBuild);  // the glossy hits' and the concentrated texels' paths, the bound: building too
    }
    for (size_t k = 0; k < build.pending.size(); ++k) {
        CachePoint& a = build.points[first + k];
        build_surfels(a);
        a.reuse_radius = std::max(a.reuse_radius, queries[build.pending[k]].min_radius);
    }
    build.used = first + build.pending.size();
    cache.lap(Stage::CacheSurfels);
}

// Each query's second cache point (build.second): the one of least error after its own, if
// within the bound. It fills the holes its own leaves before any is traced (fill_holes).
inline void choose_second_points(const CacheSettings& cfg, const Query* queries, size_t n, CacheState& cache) {
    CachePointBuild& build = cache.build;
    build.second.assign(n, -1);
    for (size_t q = 0; q < n; ++q) {
        float best = cfg.error;
        for (size_t a = 0; a < build.pool.size(); ++a) {
            if (static_cast<int32_t>(a) == build.assigned[q]) continue;
            const float e = reuse_error(*build.pool[a], queries[q].p, queries[q].n);
            if (e <= best) best = e, build.second[q] = static_cast<int32_t>(a);
        }
    }
}

// The holes A's reprojection left in B (neither filled nor decided: what A did not see,
// not the surfels B sees from behind, which hide what lies behind them) filled, where it
// knows them, by a second cache point's reprojection: geometry one point did not see
// another nearby point often did, and a lookup costs far less than a path. Returns the
// texels filled.
constexpr int kMinHolesForSecond = 8;  // fewer holes are cheaper traced than a second reprojection

inline int fill_holes(const CachePoint& a2, const Receiver& b, const TexelDirections& directions, float* radiance,
                      CacheState& cache) {
    QueryReprojection& reprojection = cache.reprojection;
    const int R = a2.resolution;
    Reprojection& assigned = reprojection.from_assigned;
    Reprojection& second = reprojection.from_second;
    int holes = 0;
    for (int y = 0; y < R; ++y) holes += row_count(assigned.to_trace.rows[y] & ~assigned.filled.rows[y]);
    if (holes < kMinHolesForSecond) return 0;
    // the second point is wanted in the holes only, and, for its cracks' test, their neighbours
    BitMask128& wanted = reprojection.holes_around;
    wanted.clear();
    const Row128 full = span_bits(0, R);
    for (int y = 0; y < R; ++y) {
        const Row128 h = assigned.to_trace.rows[y] & ~assigned.filled.rows[y];
        if (row_empty(h)) continue;
        const Row128 left = {h[0] << 1, (h[1] << 1) | (h[0] >> 63)};
        const Row128 right = {(h[0] >> 1) | (h[1] << 63), h[1] >> 1};
        wanted.rows[y] |= (h | left | right) & full;
        if (y > 0) wanted.rows[y - 1] |= h;
        if (y + 1 < R) wanted.rows[y + 1] |= h;
    }
    float* tex2 = grow(reprojection.second_texture, 3 * static_cast<size_t>(R) * R);
    reproject(a2, b, directions, tex2, second, reprojection.scratch, true, &wanted);
    int taken = 0;
    for (int y = 0; y < R; ++y) {
        const Row128 take = assigned.to_trace.rows[y] & ~assigned.filled.rows[y] & second.filled.rows[y] & ~second.to_trace.rows[y];
        if (row_empty(take)) continue;
        for_each_bit(take, [&](int x) {
            const size_t t = static_cast<size_t>(y) * R + x;
            std::copy(tex2 + 3 * t, tex2 + 3 * t + 3, radiance + 3 * t);
            ++taken;
        });
        assigned.filled.rows[y] |= take;
        assigned.to_trace.rows[y] &= ~take;
    }
    assigned.traced -= taken;
    return taken;
}

// Assigns every query a cache point (build.assigned, an index in build.pool; build.own: the query is
// that point), starting from the shared points (build.shared) and building the ones it needs.
template <class Tracer>
inline void place_cache_points(const CacheSettings& cfg, float eps, const Query* queries, size_t n,
                               CacheState& cache, Tracer& trace) {
    CachePointBuild& build = cache.build;
    static const std::vector<const CachePoint*> none;
    const std::vector<const CachePoint*>& shared = build.shared ? *build.shared : none;
    const size_t ns = shared.size();
    // point a: shared[a], or the a - ns'th built here
    auto point = [&](size_t a) -> const CachePoint& { return a < ns ? *shared[a] : build.points[a - ns]; };
    build.used = 0;
    build.assigned.assign(n, -1);
    build.own.assign(n, 0);
    for (int round = 0; round < kMaxRounds; ++round) {
        // the best existing cache point within the bound
        for (size_t q = 0; q < n; ++q) {
            if (build.assigned[q] >= 0) continue;
            float best = cfg.error;
            for (size_t a = 0; a < ns + build.used; ++a) {
                const float e = reuse_error(point(a), queries[q].p, queries[q].n);
                if (e <= best) best = e, build.assigned[q] = static_cast<int32_t>(a);
            }
        }
        // the radius new cache points are expected to have: the median of the existing ones
        float radius = INFINITY;
        if (ns + build.used > 0) {
            std::vector<float> radii;
            for (size_t a = 0; a < ns + build.used; ++a) radii.push_back(point(a).reuse_radius);
            std::nth_element(radii.begin(), radii.begin() + radii.size() / 2, radii.end());
            radius = radii[radii.size() / 2];
        }
        build.pending.clear();
        for (size_t q = 0; q < n; ++q) {
            if (build.assigned[q] >= 0) continue;
            bool near = false;
            if (round + 1 < kMaxRounds)
                for (const int32_t p : build.pending)
                    if (reuse_error(queries[p].p, queries[p].n, radius, queries[q].p, queries[q].n) <= cfg.error) {
                        near = true;
                        break;
                    }
            if (!near) build.pending.push_back(static_cast<int32_t>(q));
        }
        if (build.pending.empty()) break;
        const size_t first = ns + build.used;
        build_cache_points(cfg, eps, queries, cache, trace);
        for (size_t k = 0; k < build.pending.size(); ++k) {
            build.assigned[build.pending[k]] = static_cast<int32_t>(first + k);
            build.own[build.pending[k]] = 1;
        }
    }
    build.pool.clear();
    for (size_t a = 0; a < ns + build.used; ++a) build.pool.push_back(&point(a));
    choose_second_points(cfg, queries, n, cache);
    cache.lap(Stage::CachePlace);
}

// The members of each of n groups, in order: first[u] .. first[u + 1] in members, the
// group of member m group(m) (negative: none of them).
template <class Group>
inline void index_groups(size_t n, size_t members_count, Group group, std::vector<int32_t>& first,
                         std::vector<int32_t>& members) {
    first.assign(n + 1, 0);
    for (size_t m = 0; m < members_count; ++m)
        if (group(m) >= 0) ++first[group(m) + 1];
    for (size_t u = 0; u < n; ++u) first[u + 1] += first[u];
    members.resize(first[n]);
    std::vector<int32_t> fill(first.begin(), first.end() - 1);
    for (size_t m = 0; m < members_count; ++m)
        if (group(m) >= 0) members[fill[group(m)]++] = static_cast<int32_t>(m);
}

// Each query's members, in order (table.query_first, table.query_members), and each stored
// region hemisphere's (stored.first, stored.members), from table.member_query.
inline void index_members(CacheState& cache) {
    StoredHemispheres& stored = cache.stored;
    QueryTable& table = cache.table;
    const size_t nm = table.member_query.size();
    index_groups(table.queries.size(), nm, [&](size_t m) { return table.member_query[m]; }, table.query_first,
                 table.query_members);
    index_groups(stored.in_use.size(), nm, [&](size_t m) { return -1 - table.member_query[m]; }, stored.first,
                 stored.members);
}

// A query's members lie within kShareError x R_A of its point (A its cache point, R_A A's
// reuse radius: the scale on which the incident radiance changes, Ward's), or they would
// take light the query's point gets and they do not (a contact shadow, a corner): a member
// farther off gets a query of its own -- with the others split off the same query that lie
// within that reach of it -- reprojected from the same cache point.
// 0.3: at 0.6 and more the bundled scenes at 16 pixels wide (an 8 x 8 block half the image)
// leave the stated bias (tests/python/render/test_cache_convergence.py)
constexpr float kShareError = 0.3f;

inline void split_far_members(CacheState& cache) {
    QueryTable& table = cache.table;
    CachePointBuild& build = cache.build;
    const size_t nq = table.queries.size();
    bool split = false;
    for (size_t u = 0; u < nq; ++u) {
        const float reach = kShareError * build.pool[build.assigned[u]]->reuse_radius;
        auto within = [&](const Vec3f& p, const Vec3f& q) { return dot(p - q, p - q) <= reach * reach; };
        const size_t first_new = table.queries.size();
        for (int32_t i = table.query_first[u]; i < table.query_first[u + 1]; ++i) {
            const int32_t m = table.query_members[i];
            const Vec3f p = table.member_own[m].p;
            if (within(p, table.queries[u].p)) continue;
            int32_t to = -1;
            for (size_t v = first_new; v < table.queries.size() && to < 0; ++v)
                if (within(p, table.queries[v].p)) to = static_cast<int32_t>(v);
            if (to < 0) {
                to = static_cast<int32_t>(table.queries.size());
                table.queries.push_back(table.member_own[m]);
                table.query_point.push_back(table.member_point[m]);
                build.assigned.push_back(build.assigned[u]);
                build.second.push_back(build.second[u]);
                build.own.push_back(0);
            }
            table.member_query[m] = to;
            split = true;
        }
    }
    if (split) index_members(cache);
}

// Counts of one call, for the statistics.
struct CacheCounts {
    size_t points = 0, queries = 0, reprojected = 0, from_misses = 0, traced = 0, own = 0;
};

// Each query's incident indirect radiance over its hemisphere (R^2 texels x RGB, texel
// j * R + i of its own frame), handed to consume(q, radiance) chunk by chunk. exact: holes
// and unknown texels are traced from the query; otherwise they take the mean of the rest.
template <class Tracer, class Consume>
inline CacheCounts reconstruct_hemispheres(const CacheSettings& cfg, float eps, bool exact, CacheState& cache,
                                           Tracer& trace, Consume consume) {
    CachePointBuild& build = cache.build;
    QueryReprojection& reprojection = cache.reprojection;
    Reprojection& reprojected = reprojection.from_assigned;
    const TexelDirections& directions = cache.texel_directions;
    const QueryTable& table = cache.table;  // split_far_members adds queries
    CacheCounts counts;
    if (table.queries.empty()) {
        // nothing built: the last call's points (moved out by build_region_points) are not this call's
        build.used = 0;
        build.pool.clear();
        return counts;
    }
    const int R = cfg.resolution;
    const size_t texel_count = static_cast<size_t>(R) * R;
    cache.texel_directions.prepare(R);
    place_cache_points(cfg, eps, table.queries.data(), table.queries.size(), cache, trace);
    split_far_members(cache);
    const Query* queries = table.queries.data();
    const size_t n = table.queries.size();
    counts.queries = n;
    counts.points = build.used;
    float* tex = grow(build.textures, kChunk * 3 * texel_count);
    for (size_t c0 = 0; c0 < n; c0 += kChunk) {
        const size_t c1 = std::min(n, c0 + kChunk);
        build.rays.clear();
        for (size_t q = c0; q < c1; ++q) {
            float* out = tex + (q - c0) * 3 * texel_count;
            const CachePoint& a = *build.pool[build.assigned[q]];
            if (build.own[q]) {
                std::copy(a.radiance.begin(), a.radiance.end(), out);
                ++counts.own;
                continue;
            }
            const Query& b = queries[q];
            const Receiver receiver{b.p, b.t, b.b, b.n};
            reproject(a, receiver, directions, out, reprojected, reprojection.scratch);
            counts.reprojected += reprojected.reprojected;
            if (build.second[q] >= 0)
                counts.reprojected += fill_holes(*build.pool[build.second[q]], receiver, directions, out, cache);
            counts.from_misses += reprojected.from_misses + reprojected.cracks;
            if (!exact) {
                // guiding: the holes take the mean of what was reprojected
                double sum[3] = {0, 0, 0};
                int known = 0;
                for (int y = 0; y < R; ++y)
                    for_each_bit(reprojected.filled.rows[y] & ~reprojected.to_trace.rows[y], [&](int x) {
                        for (int k = 0; k < 3; ++k) sum[k] += out[3 * (y * R + x) + k];
                        ++known;
                    });
                for (int y = 0; y < R; ++y)
                    for_each_bit(reprojected.to_trace.rows[y], [&](int x) {
                        for (int k = 0; k < 3; ++k)
                            out[3 * (y * R + x) + k] = known > 0 ? static_cast<float>(sum[k] / known) : 0.0f;
                    });
                continue;
            }
            const uint32_t key = hole_key(b.key);
            const Vec3f o = b.p + eps * b.ng;
            for (int y = 0; y < R; ++y)
                for_each_bit(reprojected.to_trace.rows[y], [&](int x) {
                    const int32_t t = y * R + x;
                    const Vec3f d = jittered_direction(b, R, t, key);
                    std::fill(out + 3 * t, out + 3 * t + 3, 0.0f);
                    if (!(dot(d, b.ng) > 0)) return;
                    const int32_t where = static_cast<int32_t>((q - c0) * texel_count + t);
                    build.rays.push(o, d, key, static_cast<uint32_t>(t), where);
                });
        }
        cache.lap(Stage::CacheReproject);
        if (exact && build.rays.size() > 0) {
            trace_queue(cache, trace);
            counts.traced += build.rays.size();
            for (size_t r = 0; r < build.rays.size(); ++r)
                std::copy(build.results[r].rgb, build.results[r].rgb + 3,
                          tex + 3 * static_cast<size_t>(build.rays.where[r]));
            // a traced hole is one path sample too, shared by every member of the query
            for (size_t q = c0; q < c1; ++q)
                if (!build.own[q]) bound_isolated_texels(tex + (q - c0) * 3 * texel_count, R, build.luminances);
        }
        cache.lap(Stage::CacheHoles);
        for (size_t q = c0; q < c1; ++q) consume(q, tex + (q - c0) * 3 * texel_count);
        cache.lap(Stage::CacheIntegrate);
    }
    return counts;
}

}  // namespace cache
PATINA_END_TARGET
