// Reprojecting a cache point A into a nearby point B's hemisphere (docs/radiance-cache.md),
// compiled once per width (included by render/integrators/kernels_impl.h):
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
    std::vector<float> outline_u, outline_v;  // outline points in B's texel coordinates, (point, surfel)
    std::vector<int32_t> texels;              // candidate texels of one surfel
    // the candidates' directions in B's frame, and what lookup_surfel finds for each in A
    std::vector<float> texel_x, texel_y, texel_z, out_i, out_j, out_ok;
    // silhouettes' shadow corners in B's texel coordinates (project_silhouettes)
    std::vector<float> shadow_u, shadow_v, corner;
    BitMask128 region;                  // the texels wanted by the reprojection under way
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

// The most of B's texels one texel of A may fill (the ratio of the solid angles its patch of
// surface subtends from B and from A). A cache point near a wall sees the wall beside it at
// grazing angles, a long strip of it per texel, each one path sample; a point farther from
// the wall sees that strip head on over many texels, all sharing the sample. Such texels are
// traced from B instead (cache-room, seed 1: a corner point 0.03 from the red wall; the
// reconstruction 0.2 from the wall that took 1004 of its light from it took 912 with the
// bound; the image's texels reprojected 76.4 -> 70.0 %, the rest traced; docs/radiance-cache.md,
// "The light patch beside the room's corner").
constexpr float kMaxMagnification = 8.0f;
// lookup_surfel's verdict per candidate texel (out_ok): none, A's texel, or to trace
constexpr float kLookupFound = 1.0f, kLookupMagnified = 2.0f;

// Looks up A's radiance for B's candidate texels of one front-facing surfel, N at a time:
// B's ray through the texel centre cut by the surfel's plane, that point's texel in A, kept
// if it is one of the surfel's own (half a texel of slack for the outline's straight edges).
inline void lookup_surfel(const CachePoint& a, const Surfel& sf, const Receiver& b, const TexelDirections& dirs,
                          ReprojectScratch& scratch, size_t count) {
    float* cx = grow(scratch.texel_x, count);
    float* cy = grow(scratch.texel_y, count);
    float* cz = grow(scratch.texel_z, count);
    for (size_t k = 0; k < count; ++k) {
        const int32_t t = scratch.texels[k];
        cx[k] = dirs.x[t], cy[k] = dirs.y[t], cz[k] = dirs.z[t];
    }
    // results in whole blocks of N (the arrays padded), stored without a partial last block
    const size_t padded = (count + N - 1) / N * N;
    float* oi = grow(scratch.out_i, padded);
    float* oj = grow(scratch.out_j, padded);
    float* ok = grow(scratch.out_ok, padded);
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
        // in texel centres' coordinates, kept inside the surfel: read_bilinear's taps
        const F i = clamp(u - F(0.5f), F(static_cast<float>(sf.i0)), F(static_cast<float>(sf.i1 - 1)));
        const F j = clamp(v - F(0.5f), F(static_cast<float>(sf.j0)), F(static_cast<float>(sf.j1 - 1)));
        // A's texel there spread over more than kMaxMagnification of B's texels (solid angles
        // equal, so the ratio of the patch's solid angle from B to A's: (d_A / d_B)^2 cos_B /
        // cos_A): A saw the surface at grazing angles, one sample for what B resolves
        const F cos_b_dist_a3 = (F(0.0f) - c) * len * len * len;      // cos_B d_A^3
        const F cos_a_dist_a = F(0.0f) - (qx * F(sf.normal.x) + qy * F(sf.normal.y) + qz * F(sf.normal.z));  // cos_A d_A
        const auto magnified = cos_b_dist_a3 > F(kMaxMagnification) * t * t * cos_a_dist_a;
        store_n<N>(oi + k, select(valid, i, F(0.0f)));
        store_n<N>(oj + k, select(valid, j, F(0.0f)));
        store_n<N>(ok + k, select(valid, select(magnified, F(kLookupMagnified), F(kLookupFound)), F(0.0f)));
    });
}

// A's radiance at (i, j) in texel centres' coordinates (inside surfel sf's texels), bilinear
// between the four nearest texel centres of the surfel. The nearest texel alone aliases: where
// B's texel grid is shifted by a fraction of a texel against A's (parallax), some of A's
// texels are taken twice and others not at all, and when a few texels hold most of A's light
// (one path sample each) a reconstruction doubles or drops them whole (cache-room, seed 1:
// 0.2 from A, two texels holding 0.55 of A's irradiance 1.50 each taken twice, the
// reconstruction's irradiance 37 % above A's: a light patch on the right wall;
// docs/radiance-cache.md, "The light patch beside the room's corner"). A tent's samples at
// unit spacing sum to one whatever their offset, so each texel of A keeps its weight.
inline void read_bilinear(const CachePoint& a, const Surfel& sf, float i, float j, float* out) {
    const int R = a.resolution;
    const int i0 = static_cast<int>(i), j0 = static_cast<int>(j);  // i, j >= 0: truncation is floor
    const int i1 = std::min(i0 + 1, sf.i1 - 1), j1 = std::min(j0 + 1, sf.j1 - 1);
    const float wi = i - static_cast<float>(i0), wj = j - static_cast<float>(j0);
    const float* L = a.radiance.data();
    const float w00 = (1 - wi) * (1 - wj), w10 = wi * (1 - wj), w01 = (1 - wi) * wj, w11 = wi * wj;
    const size_t t00 = 3 * static_cast<size_t>(j0 * R + i0), t10 = 3 * static_cast<size_t>(j0 * R + i1);
    const size_t t01 = 3 * static_cast<size_t>(j1 * R + i0), t11 = 3 * static_cast<size_t>(j1 * R + i1);
    for (int c = 0; c < 3; ++c)
        out[c] = w00 * L[t00 + c] + w10 * L[t10 + c] + w01 * L[t01 + c] + w11 * L[t11 + c];
}

// Whether the convex hull of n points (texel coordinates) may cover a texel of `region`
// not in `taken`: false when a point is not finite (raster_convex draws nothing then) or
// when every texel of the points' bounding box, widened by a texel against rounding, is
// taken or outside the region. What such a hull would rasterize changes nothing, so the
// reprojection skips its hull and rows: most of a far layer's surfels lie behind nearer
// ones, most shadows of the second cache point fall outside the holes it is wanted in.
PATINA_INLINE bool touches_open(const float* qx, const float* qy, int n, int resolution, const BitMask128& taken,
                                const BitMask128& region, const BitMask128* also_taken = nullptr) {
    float xlo = qx[0], xhi = qx[0], ylo = qy[0], yhi = qy[0];
    for (int k = 0; k < n; ++k) {
        if (!std::isfinite(qx[k]) || !std::isfinite(qy[k])) return false;
        xlo = std::min(xlo, qx[k]), xhi = std::max(xhi, qx[k]);
        ylo = std::min(ylo, qy[k]), yhi = std::max(yhi, qy[k]);
    }
    const float side = static_cast<float>(resolution);
    if (!(xhi >= -1.0f && xlo <= side + 1.0f && yhi >= -1.0f && ylo <= side + 1.0f)) return false;
    const int x0 = std::max(0, static_cast<int>(std::floor(xlo)) - 1);
    const int x1 = std::min(resolution, static_cast<int>(std::ceil(xhi)) + 1);
    const int y0 = std::max(0, static_cast<int>(std::floor(ylo)) - 1);
    const int y1 = std::min(resolution, static_cast<int>(std::ceil(yhi)) + 1);
    if (x0 >= x1) return false;
    const Row128 span = span_bits(x0, x1);
    for (int y = y0; y < y1; ++y) {
        Row128 open = span & region.rows[y] & ~taken.rows[y];
        if (also_taken != nullptr) open = open & ~also_taken->rows[y];
        if (!row_empty(open)) return true;
    }
    return false;
}

// The shadow corners of every silhouette of A in B's texel coordinates, N silhouettes at a
// time (the same bits as one at a time: the map's polynomials are the same at every width):
// corner k of silhouette e at (sx, sy)[k * stride + e], k = 0, 1 its edge's end points, 2, 3
// the directions from A past its end points 1, 0 (the shadow's far side, at infinity).
inline void project_silhouettes(const CachePoint& a, const Receiver& b, float scale, ReprojectScratch& scratch) {
    const size_t ne = a.silhouettes.size();
    const size_t stride = (ne + N - 1) / N * N;
    float* sx = grow(scratch.shadow_u, 4 * stride);
    float* sy = grow(scratch.shadow_v, 4 * stride);
    float* c = grow(scratch.corner, 12 * stride);  // the corners' world points or directions, (coordinate, silhouette)
    for (size_t e = 0; e < ne; ++e) {
        const Silhouette& sil = a.silhouettes[e];
        const Vec3f v[4] = {sil.e0 - b.p, sil.e1 - b.p, sil.d1, sil.d0};
        for (int k = 0; k < 4; ++k) {
            c[(3 * k + 0) * stride + e] = v[k].x;
            c[(3 * k + 1) * stride + e] = v[k].y;
            c[(3 * k + 2) * stride + e] = v[k].z;
        }
    }
    for (int k = 0; k < 4; ++k)
        for_blocks(ne, [&](size_t e, int lanes) {
            V3 d{load_lanes(c + (3 * k + 0) * stride, e, lanes), load_lanes(c + (3 * k + 1) * stride, e, lanes),
                 load_lanes(c + (3 * k + 2) * stride, e, lanes)};
            if (k < 2) {  // normalize() of a point's offset, component by component
                const F len = sqrt_exact(d.x * d.x + d.y * d.y + d.z * d.z);
                const auto ok = len > F(0.0f);
                d = V3{select(ok, d.x / len, d.x), select(ok, d.y / len, d.y), select(ok, d.z / len, d.z)};
            }
            F u, v;
            hemisphere_to_square(d.x * F(b.t.x) + d.y * F(b.t.y) + d.z * F(b.t.z),
                                 d.x * F(b.b.x) + d.y * F(b.b.y) + d.z * F(b.b.z),
                                 d.x * F(b.n.x) + d.y * F(b.n.y) + d.z * F(b.n.z), u, v);
            store_n<N>(sx + k * stride + e, u * F(scale));
            store_n<N>(sy + k * stride + e, v * F(scale));
        });
}

// Silhouettes e0 .. e1's shadows (projected by project_silhouettes) into `shadows`, rows
// [ylo, yhi) touched. With a region (the second cache point's), a shadow over no wanted
// texel that is neither filled nor unknown yet is left out: it could forbid nothing, so
// only the unknown mask's bits differ, on texels already decided or not wanted.
inline void add_shadows(const CachePoint& a, int32_t e0, int32_t e1, int R, const ReprojectScratch& scratch,
                        const Reprojection& r, const BitMask128* region, BitMask128& shadows, int& ylo, int& yhi) {
    const size_t stride = (a.silhouettes.size() + N - 1) / N * N;
    for (int32_t e = e0; e < e1; ++e) {
        float qx[4], qy[4];
        for (int k = 0; k < 4; ++k) qx[k] = scratch.shadow_u[k * stride + e], qy[k] = scratch.shadow_v[k * stride + e];
        if (region != nullptr && !touches_open(qx, qy, 4, R, r.filled, *region, &r.unknown)) continue;
        raster_convex(qx, qy, 4, R, [&](int y, Row128 span) {
            shadows.rows[y] |= span;
            ylo = std::min(ylo, y), yhi = std::max(yhi, y + 1);
        });
    }
}

// The misses: a wanted open texel whose direction A saw nothing in (nor around it) has no
// indirect radiance.
inline void fill_misses(const CachePoint& a, const Receiver& b, const TexelDirections& dirs, float* radiance,
                        Reprojection& r, const BitMask128& wanted, int R) {
    const float scale = static_cast<float>(R);
    for (int y = 0; y < R; ++y) {
        const Row128 open = wanted.rows[y] & ~r.filled.rows[y] & ~r.unknown.rows[y];
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
}
// Reprojects A into B: radiance (R^2 x 3, B's texels) where filled, the masks in `r`.
// unknown_masks false leaves the silhouettes out (for the tests and pictures: the leak).
// region (nullptr: every texel): the texels wanted. Outside it the texels stay as if A had
// nothing there (not filled, to be traced); inside it everything is as without a region
// when it holds each wanted texel's four neighbours too (a crack's test reads them): the
// second cache point, wanted only in the first one's holes (fill_holes), costs their share.
inline void reproject(const CachePoint& a, const Receiver& b, const TexelDirections& dirs, float* radiance,
                      Reprojection& r, ReprojectScratch& scratch, bool unknown_masks = true,
                      const BitMask128* region = nullptr) {
    const int R = a.resolution;
    const float scale = static_cast<float>(R);
    r.filled.clear();
    r.to_trace.clear();
    r.unknown.clear();
    r.reprojected = r.from_misses = r.cracks = r.traced = 0;
    const size_t ns = a.surfels.size();
    // the outline points of N surfels at a time in B's texel coordinates
    const size_t stride = (ns + N - 1) / N * N;  // whole blocks of N per outline point
    float* px = grow(scratch.outline_u, kOutlinePoints * stride);
    float* py = grow(scratch.outline_v, kOutlinePoints * stride);
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
    if (unknown_masks) project_silhouettes(a, b, scale, scratch);
    BitMask128& wanted = scratch.region;
    if (region != nullptr) {
        wanted = *region;
    } else {
        wanted.fill_square(R);
    }
    BitMask128 layer_unknown;
    layer_unknown.clear();
    for (int layer = 0; layer < kMaxLayers; ++layer) {
        for (int32_t s = a.layer_start[layer]; s < a.layer_start[layer + 1]; ++s) {
            const Surfel& sf = a.surfels[s];
            float qx[kOutlinePoints], qy[kOutlinePoints];
            for (int k = 0; k < kOutlinePoints; ++k) qx[k] = px[k * stride + s], qy[k] = py[k * stride + s];
            if (!touches_open(qx, qy, kOutlinePoints, R, r.filled, wanted, &r.unknown)) continue;
            const bool front = dot(sf.normal, b.p - sf.point) > 0;
            scratch.texels.clear();
            raster_convex(qx, qy, kOutlinePoints, R, [&](int y, Row128 span) {
                const Row128 avail = span & wanted.rows[y] & ~r.filled.rows[y] & ~r.unknown.rows[y];
                if (row_empty(avail)) return;
                if (!front) {  // its back: A never saw it, but it hides what lies behind
                    r.filled.rows[y] |= avail;
                    r.to_trace.rows[y] |= avail;
                    return;
                }
                for_each_bit(avail, [&](int x) { scratch.texels.push_back(y * R + x); });
            });
            if (scratch.texels.empty()) continue;
            const size_t count = scratch.texels.size();
            lookup_surfel(a, sf, b, dirs, scratch, count);
            for (size_t k = 0; k < count; ++k) {
                if (scratch.out_ok[k] == 0.0f) continue;
                const int32_t t = scratch.texels[k];
                if (scratch.out_ok[k] == kLookupMagnified) {  // the surfel hides what lies behind it
                    r.filled.set(t % R, t / R);
                    r.to_trace.set(t % R, t / R);
                    continue;
                }
                read_bilinear(a, sf, scratch.out_i[k], scratch.out_j[k], radiance + 3 * t);
                r.filled.set(t % R, t / R);
                ++r.reprojected;
            }
        }
        // this layer's silhouettes: what lies behind them is unknown to every farther layer
        const int32_t e0 = a.silhouette_start[layer], e1 = a.silhouette_start[layer + 1];
        if (e0 == e1 || !unknown_masks) continue;
        int ylo = R, yhi = 0;
        add_shadows(a, e0, e1, R, scratch, r, region, layer_unknown, ylo, yhi);
        for (int y = ylo; y < yhi; ++y) {
            r.unknown.rows[y] |= layer_unknown.rows[y];
            layer_unknown.rows[y] = Row128{0, 0};
        }
    }
    const Row128 full = span_bits(0, R);
    fill_misses(a, b, dirs, radiance, r, wanted, R);
    // cracks: a hole between surfels (not unknown) whose four neighbours all took radiance
    // takes their mean instead of a ray (the neighbours as they were before any crack)
    scratch.texels.clear();
    for (int y = 1; y + 1 < R; ++y) {
        const Row128 known_above = r.filled.rows[y + 1] & ~r.to_trace.rows[y + 1];
        const Row128 known_below = r.filled.rows[y - 1] & ~r.to_trace.rows[y - 1];
        const Row128 known = r.filled.rows[y] & ~r.to_trace.rows[y];
        // bit x set where x - 1 and x + 1 are known: the row shifted by one each way
        const Row128 left = {known[0] << 1, (known[1] << 1) | (known[0] >> 63)};
        const Row128 right = {(known[0] >> 1) | (known[1] << 63), known[1] >> 1};
        const Row128 crack = wanted.rows[y] & ~r.filled.rows[y] & ~r.unknown.rows[y] & known_above & known_below & left & right;
        for_each_bit(crack, [&](int x) { scratch.texels.push_back(y * R + x); });
    }
    for (const int32_t t : scratch.texels) {
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
