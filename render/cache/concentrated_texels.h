// More paths where a cache point's light sits in a few texels (docs/radiance-cache.md, "A cache
// point's light in a few texels"). A texel is one path sample of the incident indirect light;
// a texel tens of times its neighbours (below the fireflies' bound, texel_outliers.h) is
// either a small real source (the sun through a window, a lamp's spot) or one lucky path, and
// either way every point that reprojects the cache point shares it: the IES interior's bright
// scatter on the floor, the room's corner patch (one point whose five texels held 62 % of its
// light). So after a point's first texture the texels far above their neighbourhood but under
// the fireflies' bound, and their eight neighbours, take kStrata more paths each, stratified
// within the texel, and hold the mean of all their paths: a real source is confirmed (the
// neighbours' paths find it too), a lucky path averaged down. Which texels, and in what order: plain scalar code in texel order,
// so the same choice at every SIMD width and thread count.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/constants.h"
#include "core/simd/target.h"
#include "core/vec3.h"
#include "render/cache/cache_point.h"
#include "render/cache/hemisphere.h"
#include "render/cache/ray_queue.h"
#include "render/cache/texel_outliers.h"
#include "render/samplers/rng.h"

PATINA_BEGIN_TARGET
namespace cache {

// A texel is concentrated when its luminance exceeds kConcentration times its neighbourhood's
// level: the mean of its eight neighbours or the hemisphere's mean texel, whichever is larger
// (a dark corner of an otherwise lit hemisphere does not make a dim texel stand out), and is
// below the fireflies' bound. Averaging a lucky path down removes light that is real where a
// scene's light arrives by rare paths (the room's caustics): the bench's bias on the room, paired
// over its 16 seeds against no refinement, moved -0.29 +- 0.15 % at 64 and -0.58 +- 0.17 % at 32
// (-1.32 % at 64 with the fireflies refined too; the room at -1.6 % already, the bound 2 %),
// while the IES interior's scatter went at both.
constexpr float kConcentration = 64.0f;
// At most this many concentrated texels a point, the brightest first: each costs its own and
// its neighbours' paths, 9 x kStrataSide^2 (the budget: 4 x 36 = 144 paths, a quarter of a
// 24 x 24 point's first paths).
constexpr int kMaxConcentrated = 4;
// Each refined texel's further paths: a kStrataSide x kStrataSide grid of strata within it.
constexpr int kStrataSide = 2;
constexpr int kStrata = kStrataSide * kStrataSide;

// What refine_concentrated_texels (radiance_cache_impl.h) keeps from call to call.
struct TexelRefinement {
    bool enabled = false;          // `cache` only: the guides need the light's shape, not its value
    RayQueue rays;                 // the further paths of a chunk's points
    std::vector<int32_t> texels;   // the texels refined (a ray's `where` in the chunk)
    std::vector<float> luminances; // one texture's texels' luminance
    std::vector<int32_t> chosen;   // one texture's concentrated texels, brightest first
    std::vector<uint8_t> marked;   // one texture's texels to refine
    std::vector<int32_t> selected; // ... in texel order
};

// The mean luminance of texel (x, y)'s neighbours inside the R x R square.
inline float neighbours_mean(const std::vector<float>& luminances, int R, int x, int y) {
    double sum = 0;
    int count = 0;
    for (int ny = std::max(y - 1, 0); ny <= std::min(y + 1, R - 1); ++ny)
        for (int nx = std::max(x - 1, 0); nx <= std::min(x + 1, R - 1); ++nx)
            if (nx != x || ny != y) sum += luminances[static_cast<size_t>(ny) * R + nx], ++count;
    return static_cast<float>(sum / count);
}

// The texels of the R x R texture `radiance` (RGB) to refine, in texel order, into `out`: the
// kMaxConcentrated brightest concentrated texels and their eight neighbours.
inline void select_texels_to_refine(const float* radiance, int R, TexelRefinement& refinement,
                                    std::vector<int32_t>& out) {
    std::vector<float>& luminances = refinement.luminances;
    const float hemisphere_mean = static_cast<float>(texel_luminances(radiance, R, luminances) / (R * R));
    std::vector<int32_t>& chosen = refinement.chosen;
    chosen.clear();
    for (int y = 0; y < R; ++y)
        for (int x = 0; x < R; ++x) {
            const float Y = luminances[static_cast<size_t>(y) * R + x];
            if (!(Y > kConcentration * hemisphere_mean)) continue;  // most texels
            // a firefly the bound will cut (texel_outliers.h) is the bound's: averaged here its
            // lucky path would lose more of its light than the bound takes
            if (Y > kOutlierBound * brightest_neighbour(luminances, R, x, y, 0.0f)) continue;
            if (Y > kConcentration * neighbours_mean(luminances, R, x, y)) chosen.push_back(y * R + x);
        }
    if (chosen.empty()) return;
    // the brightest first, ties by texel: the same choice whatever the order of the search
    std::stable_sort(chosen.begin(), chosen.end(), [&](int32_t a, int32_t b) { return luminances[a] > luminances[b]; });
    if (chosen.size() > static_cast<size_t>(kMaxConcentrated)) chosen.resize(kMaxConcentrated);
    std::vector<uint8_t>& marked = refinement.marked;
    marked.assign(static_cast<size_t>(R) * R, 0);
    for (const int32_t t : chosen)
        for (int ny = std::max(t / R - 1, 0); ny <= std::min(t / R + 1, R - 1); ++ny)
            for (int nx = std::max(t % R - 1, 0); nx <= std::min(t % R + 1, R - 1); ++nx)
                marked[static_cast<size_t>(ny) * R + nx] = 1;
    for (size_t t = 0; t < marked.size(); ++t)
        if (marked[t]) out.push_back(static_cast<int32_t>(t));
}

// The stream key of stratum s of a refined texel's further paths: a stream of its own for each
// stratum (the texel its index), none the point's own or a glossy hit's further paths'.
inline uint32_t stratum_key(uint32_t point_key, int s) {
    return hash_u32(point_key ^ (0x7feb352du * static_cast<uint32_t>(s + 1)));
}

// The point in the unit square of stratum s (of kStrata) of texel t of an R x R texture,
// jittered within the stratum by (jitter_u, jitter_v) in [0, 1).
inline void stratum_point(int R, int32_t t, int s, float jitter_u, float jitter_v, float& u, float& v) {
    const float su = (static_cast<float>(s % kStrataSide) + jitter_u) / kStrataSide;
    const float sv = (static_cast<float>(s / kStrataSide) + jitter_v) / kStrataSide;
    u = (static_cast<float>(t % R) + su) / R;
    v = (static_cast<float>(t / R) + sv) / R;
}

// The kStrata paths of texel t of cache point a from o (a's point lifted off its surface), one a
// stratum, into `rays` (their `where`: the caller's index of the texel); a stratum under the
// geometric surface takes no path (its light is none).
inline void push_strata(const CachePoint& a, int32_t t, uint32_t point_key, const Vec3f& o, int32_t where,
                        RayQueue& rays) {
    const int R = a.resolution;
    for (int s = 0; s < kStrata; ++s) {
        const uint32_t stream = stratum_key(point_key, s);
        float u, v, x, y, z;
        stratum_point(R, t, s, uniform(stream, 2u * t), uniform(stream, 2u * t + 1), u, v);
        square_to_hemisphere(u, v, x, y, z);
        const Vec3f d = normalize(x * a.t + y * a.b + z * a.n);
        if (dot(d, a.ng) > 0) rays.push(o, d, stream, static_cast<uint32_t>(t), where);
    }
}

}  // namespace cache
PATINA_END_TARGET
