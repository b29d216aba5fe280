// Reprojecting a cache point A into a nearby point B's hemisphere (docs/radiance-cache.md),
// compiled once per width (included by integrator_impl.h):
//   - every surfel's outline points are projected into B's parametrization N surfels at a
//     time (SIMD over surfels);
//   - layer by layer, near to far, each surfel is rasterized (render/cache/raster.h) and
//     takes the texels of its region that are neither filled (by a nearer surfel: the fill
//     mask replaces a z-buffer) nor unknown (behind a nearer layer's silhouette, where A
//     could not see). A surfel B sees from behind marks its texels filled but to be traced:
//     A never saw that side. A surfel B sees from the front takes, N texels at a time, the
//     radiance of A's texel that B's ray through the texel reaches on the surfel's plane;
//   - after each layer its silhouettes' shadows (unknown masks) are added, so they forbid
//     only farther layers;
//   - last the directions A saw nothing in (misses all around) take zero indirect radiance;
//   - whatever is left is a hole, to be traced from B, as are the texels seen from behind.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/simd/kernel_width.h"
#include "core/vec3.h"
#include "render/cache/bit_mask.h"
#include "render/cache/cache_point.h"
#include "render/cache/hemisphere.h"
#include "render/cache/raster.h"
#include "render/cache/surfels.h"

PATINA_BEGIN_TARGET
namespace cache {
using namespace kernel_width;

// The point a cache point is reprojected into: its position and hemisphere frame.
struct Receiver {
    Vec3f p, t, b, n;
};

// Directions of the texel centres of an R x R hemisphere in its local frame, as three
// arrays (x, y, z) of R^2 values, texel j * R + i.
struct TexelDirections {
    int resolution = 0;
    std::vector<float> x, y, z;
    void prepare(int r) {
        if (r == resolution) return;
        resolution = r;
        const size_t n = static_cast<size_t>(r) * r;
        x.resize(n), y.resize(n), z.resize(n);
        for (int j = 0; j < r; ++j)
            for (int i = 0; i < r; ++i) {
                const size_t k = static_cast<size_t>(j) * r + i;
                square_to_hemisphere((i + 0.5f) / r, (j + 0.5f) / r, x[k], y[k], z[k]);
            }
    }
};

// What the reprojection leaves: filled (radiance known or decided), to_trace (holes, the
// unknown, the surfels seen from behind), and counts for the statistics and the pictures.
struct Reprojection {
    BitMask128 filled, to_trace, unknown;
    int reprojected = 0, from_misses = 0, cracks = 0, traced = 0;
};

// Work arrays of one reprojection, kept from point to point.
struct ReprojectScratch {
    std::vector<float> px, py;          // outline points in B's texel coordinates, (point, surfel)
    std::vector<int32_t> texels;        // candidate texels of one surfel
    std::vector<float> cx, cy, cz, out_i, out_j, out_ok;
};

// Where a world point lands in B's square, in texel coordinates (N points at a time).
PATINA_INLINE void project_points(const Receiver& b, const V3& x, F scale, F& u, F& v) {
    const F dx = x.x - F(b.p.x), dy = x.y - F(b.p.y), dz = x.z - F(b.p.z);
    const F lx = dx * F(b.t.x) + dy * F(b.t.y) + dz * F(b.t.z);
    const F ly = dx * F(b.b.x) + dy * F(b.b.y) + dz * F(b.b.z);
    const F lz = dx * F(b.n.x) + dy * F(b.n.y) + dz * F(b.n.z);
    const F len = sqrt_exact(lx * lx + ly * ly + lz * lz);
    hemisphere_to_square(lx / len, ly / len, lz / len, u, v);
    u = u * scale;
    v = v * scale;
}

inline void project_direction(const Receiver& b, const Vec3f& d, float scale, float& u, float& v) {
    hemisphere_to_square(dot(d, b.t), dot(d, b.b), dot(d, b.n), u, v);
    u *= scale;
    v *= scale;
}

// Looks up A's radiance for B's candidate texels of one front-facing surfel, N at a time:
// B's ray through the texel centre cut by the surfel's plane, that point's texel in A, kept
// if it is one of the surfel's own (half a texel of slack for the outline's straight edges).
inline void lookup_surfel(const CachePoint& a, const Surfel& sf, const Receiver& b, const TexelDirections& dirs,
                          ReprojectScratch& rs, size_t count) {
    float* cx = grow(rs.cx, count);
    float* cy = grow(rs.cy, count);
    float* cz = grow(rs.cz, count);
    for (size_t k = 0; k < count; ++k) {
        const int32_t t = rs.texels[k];
        cx[k] = dirs.x[t], cy[k] = dirs.y[t], cz[k] = dirs.z[t];
    }
    // results in whole blocks of N (the arrays padded), stored without a partial last block
    const size_t padded = (count + N - 1) / N * N;
    float* oi = grow(rs.out_i, padded);
    float* oj = grow(rs.out_j, padded);
    float* ok = grow(rs.out_ok, padded);
    const float scale = static_cast<float>(a.resolution);
    for_blocks(count, [&](size_t k, int lanes) {
        const F lx = load_lanes(cx, k, lanes), ly = load_lanes(cy, k, lanes), lz = load_lanes(cz, k, lanes);
        const F dx = lx * F(b.t.x) + ly * F(b.b.x) + lz * F(b.n.x);
        const F dy = lx * F(b.t.y) + ly * F(b.b.y) + lz * F(b.n.y);
        const F dz = lx * F(b.t.z) + ly * F(b.b.z) + lz * F(b.n.z);
        const F c = dx * F(sf.normal.x) + dy * F(sf.normal.y) + dz * F(sf.normal.z);
        const float num = dot(sf.normal, sf.point - b.p);
        const F t = F(num) / c;
        auto valid = (c < F(0.0f)) & (t > F(0.0f));
        // the point on the plane, seen from A
        const F qx = F(b.p.x - a.p.x) + t * dx, qy = F(b.p.y - a.p.y) + t * dy, qz = F(b.p.z - a.p.z) + t * dz;
        const F ax = qx * F(a.t.x) + qy * F(a.t.y) + qz * F(a.t.z);
        const F ay = qx * F(a.b.x) + qy * F(a.b.y) + qz * F(a.b.z);
        const F az = qx * F(a.n.x) + qy * F(a.n.y) + qz * F(a.n.z);
        const F len = sqrt_exact(ax * ax + ay * ay + az * az);
        valid = valid & (az > F(0.0f)) & (len > F(0.0f));
        F u, v;
        hemisphere_to_square(ax / len, ay / len, az / len, u, v);
        u = u * F(scale);
        v = v * F(scale);
        valid = valid & (u >= F(sf.i0 - 0.5f)) & (u <= F(sf.i1 + 0.5f)) & (v >= F(sf.j0 - 0.5f)) &
                (v <= F(sf.j1 + 0.5f));
        const F i = clamp(floor(u), F(static_cast<float>(sf.i0)), F(static_cast<float>(sf.i1 - 1)));
        const F j = clamp(floor(v), F(static_cast<float>(sf.j0)), F(static_cast<float>(sf.j1 - 1)));
        store_n<N>(oi + k, select(valid, i, F(0.0f)));
        store_n<N>(oj + k, select(valid, j, F(0.0f)));
        store_n<N>(ok + k, select(valid, F(1.0f), F(0.0f)));
    });
}

// Reprojects A into B: radiance (R^2 x 3, B's texels) where filled, the masks in `r`.
// unknown_masks false leaves the silhouettes out (for the tests and pictures: the leak).
inline void reproject(const CachePoint& a, const Receiver& b, const TexelDirections& dirs, float* radiance,
                      Reprojection& r, ReprojectScratch& rs, bool unknown_masks = true) {
    const int R = a.resolution;
    const float scale = static_cast<float>(R);
    r.filled.clear();
    r.to_trace.clear();
    r.unknown.clear();
    r.reprojected = r.from_misses = r.cracks = r.traced = 0;
    const size_t ns = a.surfels.size();
    // the outline points of N surfels at a time in B's texel coordinates
    const size_t stride = (ns + N - 1) / N * N;  // whole blocks of N per outline point
    float* px = grow(rs.px, kOutlinePoints * stride);
    float* py = grow(rs.py, kOutlinePoints * stride);
    for (int k = 0; k < kOutlinePoints; ++k) {
        const float* ox = a.outline.data() + (3 * k + 0) * ns;
        const float* oy = a.outline.data() + (3 * k + 1) * ns;
        const float* oz = a.outline.data() + (3 * k + 2) * ns;
        for_blocks(ns, [&](size_t s, int lanes) {
            const V3 x{load_lanes(ox, s, lanes), load_lanes(oy, s, lanes), load_lanes(oz, s, lanes)};
            F u, v;
            project_points(b, x, F(scale), u, v);
            store_n<N>(px + k * stride + s, u);
            store_n<N>(py + k * stride + s, v);
        });
    }
    BitMask128 layer_unknown;
    layer_unknown.clear();
    for (int layer = 0; layer < kMaxLayers; ++layer) {
        for (int32_t s = a.layer_start[layer]; s < a.layer_start[layer + 1]; ++s) {
            const Surfel& sf = a.surfels[s];
            float qx[kOutlinePoints], qy[kOutlinePoints];
            for (int k = 0; k < kOutlinePoints; ++k) qx[k] = px[k * stride + s], qy[k] = py[k * stride + s];
            const bool front = dot(sf.normal, b.p - sf.point) > 0;
            rs.texels.clear();
            raster_convex(qx, qy, kOutlinePoints, R, [&](int y, Row128 span) {
                const Row128 avail = span & ~r.filled.rows[y] & ~r.unknown.rows[y];
                if (row_empty(avail)) return;
                if (!front) {  // its back: A never saw it, but it hides what lies behind
                    r.filled.rows[y] |= avail;
                    r.to_trace.rows[y] |= avail;
                    return;
                }
                for_each_bit(avail, [&](int x) { rs.texels.push_back(y * R + x); });
            });
            if (rs.texels.empty()) continue;
            const size_t count = rs.texels.size();
            lookup_surfel(a, sf, b, dirs, rs, count);
            for (size_t k = 0; k < count; ++k) {
                if (rs.out_ok[k] == 0.0f) continue;
                const int32_t t = rs.texels[k];
                const size_t src = static_cast<size_t>(rs.out_j[k]) * R + static_cast<size_t>(rs.out_i[k]);
                std::copy(a.radiance.data() + 3 * src, a.radiance.data() + 3 * src + 3, radiance + 3 * t);
                r.filled.set(t % R, t / R);
                ++r.reprojected;
            }
        }
        // this layer's silhouettes: what lies behind them is unknown to every farther layer
        const int32_t e0 = a.silhouette_start[layer], e1 = a.silhouette_start[layer + 1];
        if (e0 == e1 || !unknown_masks) continue;
        int ylo = R, yhi = 0;
        for (int32_t e = e0; e < e1; ++e) {
            const Silhouette& sil = a.silhouettes[e];
            float qx[4], qy[4];
            project_direction(b, normalize(sil.e0 - b.p), scale, qx[0], qy[0]);
            project_direction(b, normalize(sil.e1 - b.p), scale, qx[1], qy[1]);
            project_direction(b, sil.d1, scale, qx[2], qy[2]);
            project_direction(b, sil.d0, scale, qx[3], qy[3]);
            raster_convex(qx, qy, 4, R, [&](int y, Row128 span) {
                layer_unknown.rows[y] |= span;
                ylo = std::min(ylo, y), yhi = std::max(yhi, y + 1);
            });
        }
        for (int y = ylo; y < yhi; ++y) {
            r.unknown.rows[y] |= layer_unknown.rows[y];
            layer_unknown.rows[y] = Row128{0, 0};
        }
    }
    // the misses: a direction A saw nothing in (nor around it) has no indirect radiance
    const Row128 full = span_bits(0, R);
    for (int y = 0; y < R; ++y) {
        const Row128 open = full & ~r.filled.rows[y] & ~r.unknown.rows[y];
        for_each_bit(open, [&](int x) {
            const size_t t = static_cast<size_t>(y) * R + x;
            const Vec3f d = dirs.x[t] * b.t + dirs.y[t] * b.b + dirs.z[t] * b.n;
            const float az = dot(d, a.n);
            if (!(az > 0)) return;
            float u, v;
            hemisphere_to_square(dot(d, a.t), dot(d, a.b), az, u, v);
            const int i = std::min(std::max(static_cast<int>(u * scale), 0), R - 1);
            const int j = std::min(std::max(static_cast<int>(v * scale), 0), R - 1);
            const int nb[5][2] = {{i, j}, {i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}};
            for (const auto& q : nb) {
                if (q[0] < 0 || q[1] < 0 || q[0] >= R || q[1] >= R) continue;
                if (a.kind[static_cast<size_t>(q[1]) * R + q[0]] != kTexelMiss) return;
            }
            std::fill(radiance + 3 * t, radiance + 3 * t + 3, 0.0f);
            r.filled.set(x, y);
            ++r.from_misses;
        });
    }
    // cracks: a hole between surfels (not unknown) whose four neighbours all took radiance
    // takes their mean instead of a ray (the neighbours as they were before any crack)
    rs.texels.clear();
    for (int y = 1; y + 1 < R; ++y) {
        const Row128 known_above = r.filled.rows[y + 1] & ~r.to_trace.rows[y + 1];
        const Row128 known_below = r.filled.rows[y - 1] & ~r.to_trace.rows[y - 1];
        const Row128 known = r.filled.rows[y] & ~r.to_trace.rows[y];
        // bit x set where x - 1 and x + 1 are known: the row shifted by one each way
        const Row128 left = {known[0] << 1, (known[1] << 1) | (known[0] >> 63)};
        const Row128 right = {(known[0] >> 1) | (known[1] << 63), known[1] >> 1};
        const Row128 crack = full & ~r.filled.rows[y] & ~r.unknown.rows[y] & known_above & known_below & left & right;
        for_each_bit(crack, [&](int x) { rs.texels.push_back(y * R + x); });
    }
    for (const int32_t t : rs.texels) {
        const int32_t nb[4] = {t - 1, t + 1, t - R, t + R};
        for (int k = 0; k < 3; ++k)
            radiance[3 * t + k] = 0.25f * (radiance[3 * nb[0] + k] + radiance[3 * nb[1] + k] +
                                           radiance[3 * nb[2] + k] + radiance[3 * nb[3] + k]);
        r.filled.set(t % R, t / R);
        ++r.cracks;
    }
    for (int y = 0; y < R; ++y) {
        r.to_trace.rows[y] |= full & ~r.filled.rows[y];
        r.traced += row_count(r.to_trace.rows[y]);
    }
}

}  // namespace cache
PATINA_END_TARGET
