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
#include <memory>
#include <unordered_map>
#include <vector>

#include "core/simd/kernel_width.h"
#include "core/vec3.h"
#include "render/cache/bit_mask.h"
#include "render/cache/cache_point.h"
#include "render/cache/cache_settings.h"
#include "render/cache/error_criterion.h"
#include "render/cache/guided_bounces_impl.h"
#include "render/cache/hemisphere.h"
#include "render/cache/region_hemisphere.h"
#include "render/cache/reprojection_impl.h"
#include "render/cache/surfels.h"
#include "render/integrators/integrator.h"
#include "render/integrators/stage_timer.h"
#include "render/samplers/rng.h"

PATINA_BEGIN_TARGET
namespace cache {

constexpr int kMaxRounds = 6;
constexpr size_t kChunk = 32;        // points reprojected, hole-traced and consumed together
constexpr size_t kMaxWavefront = 16384;  // rays per call of the path tracer

// A point that wants its hemisphere: where, its frame, its geometric normal, its path's key,
// and the least reuse radius a cache point made here gets (error_criterion.h).
struct Query {
    Vec3f p, ng, t, b, n;
    uint32_t key;
    float min_radius = 0;
};

// Rays for the path tracer: origins, directions, the stream key and index of each (a
// hemisphere's texels are one stream, the texel its index: with the Sobol sampler the paths
// of a hemisphere are one stratified sequence); their results.
struct RayQueue {
    std::vector<float> org, dir;
    std::vector<uint32_t> keys, indices;
    std::vector<int32_t> where;  // the caller's index of each ray (a texel)
    void clear() {
        org.clear(), dir.clear(), keys.clear(), indices.clear(), where.clear();
    }
    void push(const Vec3f& o, const Vec3f& d, uint32_t key, uint32_t index, int32_t at) {
        org.insert(org.end(), {o.x, o.y, o.z});
        dir.insert(dir.end(), {d.x, d.y, d.z});
        keys.push_back(key);
        indices.push_back(index);
        where.push_back(at);
    }
    size_t size() const { return keys.size(); }
};

// Everything one worker's cache keeps from call to call (memory only, no results).
struct CacheState {
    PathScratch inner;                      // the path tracer's scratch for the cache's own rays
    std::vector<CameraSample> inner_samples;
    // Two levels of sharing (cache_stages_impl.h, collect_queries): a *query* is one
    // reconstructed hemisphere, shared by the pixels of a block whose points lie close; a
    // *member* is one pixel's integration of it against its own BRDF and view, shared by
    // that pixel's samples.
    std::vector<Query> queries;
    std::vector<int32_t> query_point;       // each query's shading point (its frame)
    std::vector<int32_t> member_point;      // each member's shading point (its view and BRDF)
    std::vector<int32_t> member_query;      // each member's query (-1 - s: the region's hemisphere stored[s])
    std::vector<Query> member_own;          // each member's own point, were it a query
    std::vector<int32_t> query_first, query_members;  // query u's members: [first[u], first[u + 1])
    std::vector<int32_t> query_of;          // each shading point's member (-1: none)
    std::unordered_map<int64_t, int32_t> pixel_member;  // by pixel_member_key: (pixel, hemisphere drawn)
    std::unordered_map<int64_t, std::vector<int32_t>> block_queries;  // a block's queries (of one material)
    // the hemispheres the item's regions reconstructed (region_hemisphere.h): by block, the
    // indices in PathScratch::cache_shared_hemispheres, and by pixel; those the batch uses, and
    // their members
    std::unordered_map<int64_t, std::vector<int32_t>> block_hemispheres;
    std::unordered_map<int64_t, int32_t> pixel_hemisphere;  // a pixel's (RegionHemisphere::pixels)
    std::vector<const RegionHemisphere*> stored;
    std::vector<int32_t> stored_slot;  // per PathScratch::cache_shared_hemispheres: its index in stored, or -1
    std::vector<int32_t> stored_first, stored_members;  // stored[s]'s members: [first[s], first[s + 1])
    std::vector<float> sums;                // cache: each member's indirect light (RGB)
    std::vector<float> l, v, eta, f, pdf, u0, u1, u2, rgb;  // integrating one hemisphere
    std::vector<float> lobe_l;  // a narrow lobe's sampled directions
    std::vector<float> split_weight;  // split_narrow_lobes: each ray's f cos / (pdf K), RGB
    std::vector<uint8_t> chose_guide;  // cache-guided: per first-hit point, drawn from the guide
    std::vector<float> guide_pick;     // ...and the uniform that picks its texel
    GuidePool guides;  // cache-guided: the batch's cache points as guides (guided_bounces_impl.h)
    std::vector<CachePoint> points;  // built by this call: [0, used)
    size_t used = 0;
    // the cache points a call starts from (the regions', PathScratch::cache_shared; none: null)
    const std::vector<const CachePoint*>* shared = nullptr;
    std::vector<const CachePoint*> pool;  // after placement: the shared points, then [0, used)
    TexelDirections dirs;
    ReprojectScratch rs;
    Reprojection rep, rep2;  // a query's reprojection, and its second cache point's (fill_holes)
    BitMask128 holes_around;  // the texels the second cache point is wanted in (fill_holes)
    std::vector<float> texture2;  // the second cache point's reprojected texture (R^2 x 3)
    std::vector<int32_t> second;  // per query: the cache point that fills its holes (in pool), or -1
    RayQueue rays;
    std::vector<PathResult> results;
    std::vector<int32_t> assigned;
    std::vector<uint8_t> own;
    std::vector<float> textures;  // kChunk x R^2 x 3
    std::vector<int32_t> pending;
    // per material: whether a cache point's texel hit on it takes hit_paths paths from the hit
    // (split_glossy_hits; empty: none, as for the guides, which need the light's shape only)
    std::vector<uint8_t> split_material;
    int hit_paths = 1;
    RayQueue split_rays;
    std::vector<int32_t> split_texels;
    StageTimer* timer = nullptr;  // the worker's: the cache's stages are laps of it
    void lap(Stage s) {
        if (timer) timer->lap(s);
    }
};

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

// Traces the queue in wavefronts of at most kMaxWavefront rays; results in st.results.
template <class Tracer>
inline void trace_queue(CacheState& st, Tracer& trace) {
    const size_t n = st.rays.size();
    st.results.resize(n);
    for (size_t a = 0; a < n; a += kMaxWavefront) {
        const size_t m = std::min(kMaxWavefront, n - a);
        trace(st.rays.org.data() + 3 * a, st.rays.dir.data() + 3 * a, st.rays.keys.data() + a,
              st.rays.indices.data() + a, m, st.results.data() + a);
    }
}

// The texels just traced (st.rays, st.results) whose first hit is on a glossy material
// (st.split_material) take st.hit_paths paths from that hit -- the texel's ray traced again
// with streams of their own -- and the mean of them: unbiased (every path is one sample of the
// light leaving the same hit towards A), and the light such a hit sends A is where a cache
// point's heavy tail is (docs/radiance-cache.md, "Bias"): the sun in the glossy lobe, caught
// by one light or BRDF sample of the texel's one path, shared by every point reusing A.
// texel(where) is the radiance (RGB) of the texel of a ray's `where`, its first path's in it.
template <class Tracer, class Texel>
inline void split_glossy_hits(CacheState& st, Tracer& trace, Texel texel) {
    const int K = st.hit_paths;
    if (K < 2 || st.split_material.empty()) return;
    st.split_rays.clear();
    st.split_texels.clear();
    for (size_t r = 0; r < st.rays.size(); ++r) {
        const int32_t m = st.results[r].material;
        if (m < 0 || static_cast<size_t>(m) >= st.split_material.size() || !st.split_material[m]) continue;
        const Vec3f o = load_vec3(st.rays.org.data() + 3 * r), d = load_vec3(st.rays.dir.data() + 3 * r);
        for (int s = 1; s < K; ++s)
            st.split_rays.push(o, d, split_path_key(st.rays.keys[r], s), st.rays.indices[r], st.rays.where[r]);
        st.split_texels.push_back(st.rays.where[r]);
    }
    if (st.split_texels.empty()) return;
    std::swap(st.rays, st.split_rays);
    trace_queue(st, trace);
    for (size_t r = 0; r < st.rays.size(); ++r) {
        float* L = texel(st.rays.where[r]);
        for (int c = 0; c < 3; ++c) L[c] += st.results[r].rgb[c];
    }
    const float share = 1.0f / static_cast<float>(K);
    for (const int32_t w : st.split_texels) {
        float* L = texel(w);
        for (int c = 0; c < 3; ++c) L[c] *= share;
    }
    std::swap(st.rays, st.split_rays);
}

// Builds cache points at the queries st.pending (appended to st.points), tracing the
// hemispheres of kChunk of them together: the ray queue and its results stay bounded however
// many points a region needs (at --cache-error 0.01 and --cache-block 1 a region's hundreds of
// points in one queue were its largest allocation; docs/radiance-cache.md). Each ray's numbers
// are its own key's, so the points are the same bits whatever the chunk.
template <class Tracer>
inline void build_cache_points(const CacheSettings& cfg, float eps, const Query* queries, CacheState& st,
                               Tracer& trace) {
    const int R = cfg.resolution;
    const size_t T = static_cast<size_t>(R) * R;
    const size_t first = st.used;
    if (st.points.size() < first + st.pending.size()) st.points.resize(first + st.pending.size());
    for (size_t k0 = 0; k0 < st.pending.size(); k0 += kChunk) {
        const size_t k1 = std::min(st.pending.size(), k0 + kChunk);
        CachePoint* chunk = st.points.data() + first + k0;
        st.rays.clear();
        for (size_t k = k0; k < k1; ++k) {
            const Query& q = queries[st.pending[k]];
            CachePoint& a = chunk[k - k0];
            a.p = q.p, a.ng = q.ng, a.t = q.t, a.b = q.b, a.n = q.n;
            a.resolution = R;
            a.radiance.assign(3 * T, 0.0f);
            a.dist.assign(T, INFINITY);
            a.kind.assign(T, kTexelBelow);
            a.hit_point.assign(3 * T, 0.0f);
            a.hit_normal.assign(3 * T, 0.0f);
            const uint32_t key = cache_point_key(q.key);
            const Vec3f o = q.p + eps * q.ng;
            for (size_t t = 0; t < T; ++t) {
                const Vec3f d = jittered_direction(q, R, static_cast<int32_t>(t), key);
                if (!(dot(d, q.ng) > 0)) continue;  // under the geometric surface: no light from there
                st.rays.push(o, d, key, static_cast<uint32_t>(t), static_cast<int32_t>((k - k0) * T + t));
            }
        }
        st.lap(Stage::CachePlace);
        trace_queue(st, trace);
        st.lap(Stage::CacheBuild);
        for (size_t r = 0; r < st.rays.size(); ++r) {
            const size_t k = st.rays.where[r] / T, t = st.rays.where[r] % T;
            CachePoint& a = chunk[k];
            const PathResult& res = st.results[r];
            std::copy(res.rgb, res.rgb + 3, a.radiance.data() + 3 * t);
            if (!(res.depth < INFINITY)) {
                a.kind[t] = kTexelMiss;
                continue;
            }
            const Vec3f d = load_vec3(st.rays.dir.data() + 3 * r);
            a.kind[t] = kTexelHit;
            a.dist[t] = res.depth;
            store_vec3(a.p + res.depth * d, a.hit_point.data() + 3 * t);
            Vec3f m = load_vec3(res.normal);
            // lights and backs of one-sided surfaces leave no normal: a surfel facing A
            if (!(dot(m, m) > 0.5f) || dot(m, d) > 0) m = -d;
            store_vec3(m, a.hit_normal.data() + 3 * t);
        }
        split_glossy_hits(st, trace, [&](int32_t w) { return chunk[w / T].radiance.data() + 3 * (w % T); });
        st.lap(Stage::CacheBuild);  // the glossy hits' paths: building too
    }
    for (size_t k = 0; k < st.pending.size(); ++k) {
        CachePoint& a = st.points[first + k];
        build_surfels(a);
        a.reuse_radius = std::max(a.reuse_radius, queries[st.pending[k]].min_radius);
    }
    st.used = first + st.pending.size();
    st.lap(Stage::CacheSurfels);
}

// Each query's second cache point (st.second): the one of least error after its own, if
// within the bound. It fills the holes its own leaves before any is traced (fill_holes).
inline void choose_second_points(const CacheSettings& cfg, const Query* queries, size_t n, CacheState& st) {
    st.second.assign(n, -1);
    for (size_t q = 0; q < n; ++q) {
        float best = cfg.error;
        for (size_t a = 0; a < st.pool.size(); ++a) {
            if (static_cast<int32_t>(a) == st.assigned[q]) continue;
            const float e = reuse_error(*st.pool[a], queries[q].p, queries[q].n);
            if (e <= best) best = e, st.second[q] = static_cast<int32_t>(a);
        }
    }
}

// The holes A's reprojection left in B (neither filled nor decided: what A did not see,
// not the surfels B sees from behind, which hide what lies behind them) filled, where it
// knows them, by a second cache point's reprojection: geometry one point did not see
// another nearby point often did, and a lookup costs far less than a path. Returns the
// texels filled.
constexpr int kMinHolesForSecond = 8;  // fewer holes are cheaper traced than a second reprojection

inline int fill_holes(const CachePoint& a2, const Receiver& b, const TexelDirections& dirs, float* radiance,
                      CacheState& st) {
    const int R = a2.resolution;
    Reprojection& r = st.rep;
    int holes = 0;
    for (int y = 0; y < R; ++y) holes += row_count(r.to_trace.rows[y] & ~r.filled.rows[y]);
    if (holes < kMinHolesForSecond) return 0;
    // the second point is wanted in the holes only, and, for its cracks' test, their neighbours
    BitMask128& wanted = st.holes_around;
    wanted.clear();
    const Row128 full = span_bits(0, R);
    for (int y = 0; y < R; ++y) {
        const Row128 h = r.to_trace.rows[y] & ~r.filled.rows[y];
        if (row_empty(h)) continue;
        const Row128 left = {h[0] << 1, (h[1] << 1) | (h[0] >> 63)};
        const Row128 right = {(h[0] >> 1) | (h[1] << 63), h[1] >> 1};
        wanted.rows[y] |= (h | left | right) & full;
        if (y > 0) wanted.rows[y - 1] |= h;
        if (y + 1 < R) wanted.rows[y + 1] |= h;
    }
    float* tex2 = grow(st.texture2, 3 * static_cast<size_t>(R) * R);
    reproject(a2, b, dirs, tex2, st.rep2, st.rs, true, &wanted);
    int taken = 0;
    for (int y = 0; y < R; ++y) {
        const Row128 take = r.to_trace.rows[y] & ~r.filled.rows[y] & st.rep2.filled.rows[y] & ~st.rep2.to_trace.rows[y];
        if (row_empty(take)) continue;
        for_each_bit(take, [&](int x) {
            const size_t t = static_cast<size_t>(y) * R + x;
            std::copy(tex2 + 3 * t, tex2 + 3 * t + 3, radiance + 3 * t);
            ++taken;
        });
        r.filled.rows[y] |= take;
        r.to_trace.rows[y] &= ~take;
    }
    r.traced -= taken;
    return taken;
}

// Assigns every query a cache point (st.assigned, an index in st.pool; st.own: the query is
// that point), starting from the shared points (st.shared) and building the ones it needs.
template <class Tracer>
inline void place_cache_points(const CacheSettings& cfg, float eps, const Query* queries, size_t n,
                               CacheState& st, Tracer& trace) {
    static const std::vector<const CachePoint*> none;
    const std::vector<const CachePoint*>& shared = st.shared ? *st.shared : none;
    const size_t ns = shared.size();
    // point a: shared[a], or the a - ns'th built here
    auto point = [&](size_t a) -> const CachePoint& { return a < ns ? *shared[a] : st.points[a - ns]; };
    st.used = 0;
    st.assigned.assign(n, -1);
    st.own.assign(n, 0);
    for (int round = 0; round < kMaxRounds; ++round) {
        // the best existing cache point within the bound
        for (size_t q = 0; q < n; ++q) {
            if (st.assigned[q] >= 0) continue;
            float best = cfg.error;
            for (size_t a = 0; a < ns + st.used; ++a) {
                const float e = reuse_error(point(a), queries[q].p, queries[q].n);
                if (e <= best) best = e, st.assigned[q] = static_cast<int32_t>(a);
            }
        }
        // the radius new cache points are expected to have: the median of the existing ones
        float radius = INFINITY;
        if (ns + st.used > 0) {
            std::vector<float> radii;
            for (size_t a = 0; a < ns + st.used; ++a) radii.push_back(point(a).reuse_radius);
            std::nth_element(radii.begin(), radii.begin() + radii.size() / 2, radii.end());
            radius = radii[radii.size() / 2];
        }
        st.pending.clear();
        for (size_t q = 0; q < n; ++q) {
            if (st.assigned[q] >= 0) continue;
            bool near = false;
            if (round + 1 < kMaxRounds)
                for (const int32_t p : st.pending)
                    if (reuse_error(queries[p].p, queries[p].n, radius, queries[q].p, queries[q].n) <= cfg.error) {
                        near = true;
                        break;
                    }
            if (!near) st.pending.push_back(static_cast<int32_t>(q));
        }
        if (st.pending.empty()) break;
        const size_t first = ns + st.used;
        build_cache_points(cfg, eps, queries, st, trace);
        for (size_t k = 0; k < st.pending.size(); ++k) {
            st.assigned[st.pending[k]] = static_cast<int32_t>(first + k);
            st.own[st.pending[k]] = 1;
        }
    }
    st.pool.clear();
    for (size_t a = 0; a < ns + st.used; ++a) st.pool.push_back(&point(a));
    choose_second_points(cfg, queries, n, st);
    st.lap(Stage::CachePlace);
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

// Each query's members, in order (st.query_first, st.query_members), and each stored
// region hemisphere's (st.stored_first, st.stored_members), from st.member_query.
inline void index_members(CacheState& st) {
    const size_t nm = st.member_query.size();
    index_groups(st.queries.size(), nm, [&](size_t m) { return st.member_query[m]; }, st.query_first,
                 st.query_members);
    index_groups(st.stored.size(), nm, [&](size_t m) { return -1 - st.member_query[m]; }, st.stored_first,
                 st.stored_members);
}

// A query's members lie within kShareError x R_A of its point (A its cache point, R_A A's
// reuse radius: the scale on which the incident radiance changes, Ward's), or they would
// take light the query's point gets and they do not (a contact shadow, a corner): a member
// farther off gets a query of its own -- with the others split off the same query that lie
// within that reach of it -- reprojected from the same cache point.
// 0.3: at 0.6 and more the bundled scenes at 16 pixels wide (an 8 x 8 block half the image)
// leave the stated bias (tests/python/render/test_cache_convergence.py)
constexpr float kShareError = 0.3f;

inline void split_far_members(CacheState& st) {
    const size_t nq = st.queries.size();
    bool split = false;
    for (size_t u = 0; u < nq; ++u) {
        const float reach = kShareError * st.pool[st.assigned[u]]->reuse_radius;
        auto within = [&](const Vec3f& p, const Vec3f& q) { return dot(p - q, p - q) <= reach * reach; };
        const size_t first_new = st.queries.size();
        for (int32_t i = st.query_first[u]; i < st.query_first[u + 1]; ++i) {
            const int32_t m = st.query_members[i];
            const Vec3f p = st.member_own[m].p;
            if (within(p, st.queries[u].p)) continue;
            int32_t to = -1;
            for (size_t v = first_new; v < st.queries.size() && to < 0; ++v)
                if (within(p, st.queries[v].p)) to = static_cast<int32_t>(v);
            if (to < 0) {
                to = static_cast<int32_t>(st.queries.size());
                st.queries.push_back(st.member_own[m]);
                st.query_point.push_back(st.member_point[m]);
                st.assigned.push_back(st.assigned[u]);
                st.second.push_back(st.second[u]);
                st.own.push_back(0);
            }
            st.member_query[m] = to;
            split = true;
        }
    }
    if (split) index_members(st);
}

// Counts of one call, for the statistics.
struct CacheCounts {
    size_t points = 0, queries = 0, reprojected = 0, from_misses = 0, traced = 0, own = 0;
};

// Each query's incident indirect radiance over its hemisphere (R^2 texels x RGB, texel
// j * R + i of its own frame), handed to consume(q, radiance) chunk by chunk. exact: holes
// and unknown texels are traced from the query; otherwise they take the mean of the rest.
template <class Tracer, class Consume>
inline CacheCounts reconstruct_hemispheres(const CacheSettings& cfg, float eps, bool exact, CacheState& st,
                                           Tracer& trace, Consume consume) {
    CacheCounts counts;
    if (st.queries.empty()) return counts;
    const int R = cfg.resolution;
    const size_t T = static_cast<size_t>(R) * R;
    st.dirs.prepare(R);
    place_cache_points(cfg, eps, st.queries.data(), st.queries.size(), st, trace);
    split_far_members(st);
    const Query* queries = st.queries.data();
    const size_t n = st.queries.size();
    counts.queries = n;
    counts.points = st.used;
    float* tex = grow(st.textures, kChunk * 3 * T);
    for (size_t c0 = 0; c0 < n; c0 += kChunk) {
        const size_t c1 = std::min(n, c0 + kChunk);
        st.rays.clear();
        for (size_t q = c0; q < c1; ++q) {
            float* out = tex + (q - c0) * 3 * T;
            const CachePoint& a = *st.pool[st.assigned[q]];
            if (st.own[q]) {
                std::copy(a.radiance.begin(), a.radiance.end(), out);
                ++counts.own;
                continue;
            }
            const Query& b = queries[q];
            const Receiver receiver{b.p, b.t, b.b, b.n};
            reproject(a, receiver, st.dirs, out, st.rep, st.rs);
            counts.reprojected += st.rep.reprojected;
            if (st.second[q] >= 0) counts.reprojected += fill_holes(*st.pool[st.second[q]], receiver, st.dirs, out, st);
            counts.from_misses += st.rep.from_misses + st.rep.cracks;
            if (!exact) {
                // guiding: the holes take the mean of what was reprojected
                double sum[3] = {0, 0, 0};
                int known = 0;
                for (int y = 0; y < R; ++y)
                    for_each_bit(st.rep.filled.rows[y] & ~st.rep.to_trace.rows[y], [&](int x) {
                        for (int k = 0; k < 3; ++k) sum[k] += out[3 * (y * R + x) + k];
                        ++known;
                    });
                for (int y = 0; y < R; ++y)
                    for_each_bit(st.rep.to_trace.rows[y], [&](int x) {
                        for (int k = 0; k < 3; ++k)
                            out[3 * (y * R + x) + k] = known > 0 ? static_cast<float>(sum[k] / known) : 0.0f;
                    });
                continue;
            }
            const uint32_t key = hole_key(b.key);
            const Vec3f o = b.p + eps * b.ng;
            for (int y = 0; y < R; ++y)
                for_each_bit(st.rep.to_trace.rows[y], [&](int x) {
                    const int32_t t = y * R + x;
                    const Vec3f d = jittered_direction(b, R, t, key);
                    std::fill(out + 3 * t, out + 3 * t + 3, 0.0f);
                    if (!(dot(d, b.ng) > 0)) return;
                    st.rays.push(o, d, key, static_cast<uint32_t>(t), static_cast<int32_t>((q - c0) * T + t));
                });
        }
        st.lap(Stage::CacheReproject);
        if (exact && st.rays.size() > 0) {
            trace_queue(st, trace);
            counts.traced += st.rays.size();
            for (size_t r = 0; r < st.rays.size(); ++r)
                std::copy(st.results[r].rgb, st.results[r].rgb + 3, tex + 3 * static_cast<size_t>(st.rays.where[r]));
        }
        st.lap(Stage::CacheHoles);
        for (size_t q = c0; q < c1; ++q) consume(q, tex + (q - c0) * 3 * T);
        st.lap(Stage::CacheIntegrate);
    }
    return counts;
}

// The worker's cache state kept in its PathScratch (made at first use, at this width).
inline CacheState& cache_state(PathScratch& sc) {
    if (!sc.cache || sc.cache_width != N) {
        sc.cache = std::unique_ptr<void, void (*)(void*)>(new CacheState(),
                                                          [](void* p) { delete static_cast<CacheState*>(p); });
        sc.cache_width = N;
    }
    return *static_cast<CacheState*>(sc.cache.get());
}

}  // namespace cache
PATINA_END_TARGET
