// Building a cache point's surfels from its traced hemisphere (docs/radiance-cache.md):
//  1. depth layers: a hit at distance d is in layer floor(kLayersPerOctave log2(d / d_min)),
//     so a layer spans a distance ratio of 2^(1/2) and reprojection can go near to far;
//  2. every hit is a surfel; inside a layer, aligned 4 x 4 and then 2 x 2 blocks of texels
//     merge into one surfel when all their normals are within kMergeAngle of their mean and
//     all their hits within kPlaneTolerance (of the distance) of their mean plane;
//  3. each surfel's outline: its block's border rays from A (corners and edge midpoints, in
//     the hemisphere parametrization) cut by its plane -- the surfel covers exactly its texels
//     as A sees them;
//  4. silhouettes: texel edges where the neighbour is a miss, under the surface, or more than
//     kSilhouetteJump farther, the edges of the space A could not see.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/vec3.h"
#include "render/cache/cache_point.h"
#include "render/cache/hemisphere.h"

PATINA_BEGIN_TARGET
namespace cache {

constexpr int kLayersPerOctave = 2;
constexpr int kMaxLayers = 32;
constexpr float kMergeCos = 0.98480775f;  // cos 10 degrees: kMergeAngle
constexpr float kPlaneTolerance = 0.02f;
constexpr float kSilhouetteJump = 0.25f;

// The world direction of square point (u, v) of a cache point's hemisphere.
inline Vec3f square_direction(const CachePoint& a, float u, float v) {
    float x, y, z;
    square_to_hemisphere(u, v, x, y, z);
    return normalize(x * a.t + y * a.b + z * a.n);
}

// Where the ray from A along d meets the plane (point q, normal m), or, where it meets it
// at a grazing angle or far from the block's hits (dlo..dhi), the point at distance dmean.
inline Vec3f on_plane(const CachePoint& a, const Vec3f& d, const Vec3f& q, const Vec3f& m, float dlo, float dhi,
                      float dmean) {
    const float c = dot(m, d);
    if (c < -0.02f) {
        const float t = dot(m, q - a.p) / c;
        if (t >= 0.5f * dlo && t <= 2.0f * dhi) return a.p + t * d;
    }
    return a.p + dmean * d;
}

inline int depth_layer(float d, float dmin) {
    const int k = static_cast<int>(std::floor(kLayersPerOctave * std::log2(std::max(d / dmin, 1.0f))));
    return std::min(std::max(k, 0), kMaxLayers - 1);
}

// Fills a's surfels, layers, outlines, silhouettes and reuse radius from its texels.
inline void build_surfels(CachePoint& a) {
    const int R = a.resolution;
    const size_t texel_count = static_cast<size_t>(R) * R;
    a.surfels.clear();
    a.silhouettes.clear();
    float dmin = INFINITY, inv_sum = 0;
    int hits = 0;
    for (size_t k = 0; k < texel_count; ++k)
        if (a.kind[k] == kTexelHit) {
            dmin = std::min(dmin, a.dist[k]);
            inv_sum += 1.0f / std::max(a.dist[k], 1e-20f);
            ++hits;
        }
    a.reuse_radius = hits > 0 ? static_cast<float>(hits) / inv_sum : INFINITY;
    std::vector<int> layer(texel_count, -1), owner(texel_count, -1);
    for (size_t k = 0; k < texel_count; ++k)
        if (a.kind[k] == kTexelHit) layer[k] = depth_layer(a.dist[k], dmin);
    auto point = [&](size_t k) { return load_vec3(a.hit_point.data() + 3 * k); };
    auto normal = [&](size_t k) { return load_vec3(a.hit_normal.data() + 3 * k); };
    const float inv_r = 1.0f / static_cast<float>(R);
    // a block of texels as one surfel, if it is one plane of one layer (size 1 always is)
    auto try_block = [&](int i0, int j0, int s) {
        const size_t first = static_cast<size_t>(j0) * R + i0;
        Vec3f nsum{0, 0, 0}, psum{0, 0, 0};
        float dlo = INFINITY, dhi = 0, dsum = 0;
        for (int j = j0; j < j0 + s; ++j)
            for (int i = i0; i < i0 + s; ++i) {
                const size_t k = static_cast<size_t>(j) * R + i;
                if (a.kind[k] != kTexelHit || owner[k] >= 0 || layer[k] != layer[first]) return;
                nsum = nsum + normal(k);
                psum = psum + point(k);
                dlo = std::min(dlo, a.dist[k]);
                dhi = std::max(dhi, a.dist[k]);
                dsum += a.dist[k];
            }
        const float count = static_cast<float>(s * s);
        const Vec3f m = normalize(nsum);
        const Vec3f q = (1.0f / count) * psum;
        const float dmean = dsum / count;
        if (s > 1)
            for (int j = j0; j < j0 + s; ++j)
                for (int i = i0; i < i0 + s; ++i) {
                    const size_t k = static_cast<size_t>(j) * R + i;
                    if (dot(normal(k), m) < kMergeCos || std::abs(dot(m, point(k) - q)) > kPlaneTolerance * dmean)
                        return;
                }
        Surfel sf;
        sf.point = q;
        sf.normal = m;
        sf.i0 = static_cast<int16_t>(i0);
        sf.j0 = static_cast<int16_t>(j0);
        sf.i1 = static_cast<int16_t>(i0 + s);
        sf.j1 = static_cast<int16_t>(j0 + s);
        sf.layer = layer[first];
        const int id = static_cast<int>(a.surfels.size());
        a.surfels.push_back(sf);
        for (int j = j0; j < j0 + s; ++j)
            for (int i = i0; i < i0 + s; ++i) owner[static_cast<size_t>(j) * R + i] = id;
    };
    for (int s : {4, 2, 1})
        for (int j0 = 0; j0 + s <= R; j0 += s)
            for (int i0 = 0; i0 + s <= R; i0 += s) try_block(i0, j0, s);

    // silhouette edges, on the plane of the texel's surfel
    for (int j = 0; j < R; ++j)
        for (int i = 0; i < R; ++i) {
            const size_t k = static_cast<size_t>(j) * R + i;
            if (a.kind[k] != kTexelHit) continue;
            const Surfel& sf = a.surfels[owner[k]];
            // neighbours right, left, up, down and the texel-corner pairs of the shared edge
            const int nb[4][2] = {{i + 1, j}, {i - 1, j}, {i, j + 1}, {i, j - 1}};
            const int edge[4][4] = {{i + 1, j, i + 1, j + 1}, {i, j + 1, i, j}, {i + 1, j + 1, i, j + 1},
                                    {i, j, i + 1, j}};
            for (int e = 0; e < 4; ++e) {
                const int ni = nb[e][0], nj = nb[e][1];
                if (ni < 0 || nj < 0 || ni >= R || nj >= R) continue;
                const size_t kn = static_cast<size_t>(nj) * R + ni;
                const bool jump = a.kind[kn] != kTexelHit || a.dist[kn] > a.dist[k] * (1.0f + kSilhouetteJump);
                if (!jump) continue;
                Silhouette silhouette;
                silhouette.d0 = square_direction(a, edge[e][0] * inv_r, edge[e][1] * inv_r);
                silhouette.d1 = square_direction(a, edge[e][2] * inv_r, edge[e][3] * inv_r);
                silhouette.e0 = on_plane(a, silhouette.d0, sf.point, sf.normal, a.dist[k], a.dist[k], a.dist[k]);
                silhouette.e1 = on_plane(a, silhouette.d1, sf.point, sf.normal, a.dist[k], a.dist[k], a.dist[k]);
                silhouette.layer = sf.layer;
                a.silhouettes.push_back(silhouette);
            }
        }

    // near to far; outlines as structure of arrays
    std::stable_sort(a.surfels.begin(), a.surfels.end(),
                     [](const Surfel& x, const Surfel& y) { return x.layer < y.layer; });
    std::stable_sort(a.silhouettes.begin(), a.silhouettes.end(),
                     [](const Silhouette& x, const Silhouette& y) { return x.layer < y.layer; });
    a.layer_start.assign(kMaxLayers + 1, 0);
    a.silhouette_start.assign(kMaxLayers + 1, 0);
    for (const Surfel& sf : a.surfels) ++a.layer_start[sf.layer + 1];
    for (const Silhouette& s : a.silhouettes) ++a.silhouette_start[s.layer + 1];
    for (int l = 0; l < kMaxLayers; ++l) {
        a.layer_start[l + 1] += a.layer_start[l];
        a.silhouette_start[l + 1] += a.silhouette_start[l];
    }
    const size_t ns = a.surfels.size();
    a.outline.assign(3 * kOutlinePoints * ns, 0.0f);
    for (size_t s = 0; s < ns; ++s) {
        const Surfel& sf = a.surfels[s];
        const float im = 0.5f * (sf.i0 + sf.i1), jm = 0.5f * (sf.j0 + sf.j1);
        const float pts[kOutlinePoints][2] = {{float(sf.i0), float(sf.j0)}, {im, float(sf.j0)},
                                              {float(sf.i1), float(sf.j0)}, {float(sf.i1), jm},
                                              {float(sf.i1), float(sf.j1)}, {im, float(sf.j1)},
                                              {float(sf.i0), float(sf.j1)}, {float(sf.i0), jm}};
        float dlo = INFINITY, dhi = 0, dsum = 0;
        for (int j = sf.j0; j < sf.j1; ++j)
            for (int i = sf.i0; i < sf.i1; ++i) {
                const float d = a.dist[static_cast<size_t>(j) * R + i];
                dlo = std::min(dlo, d), dhi = std::max(dhi, d), dsum += d;
            }
        const float dmean = dsum / static_cast<float>((sf.i1 - sf.i0) * (sf.j1 - sf.j0));
        for (int k = 0; k < kOutlinePoints; ++k) {
            const Vec3f d = square_direction(a, pts[k][0] * inv_r, pts[k][1] * inv_r);
            const Vec3f x = on_plane(a, d, sf.point, sf.normal, dlo, dhi, dmean);
            a.outline[(3 * k + 0) * ns + s] = x.x;
            a.outline[(3 * k + 1) * ns + s] = x.y;
            a.outline[(3 * k + 2) * ns + s] = x.z;
        }
    }
}

}  // namespace cache
PATINA_END_TARGET
