// The radiance cache's pieces on known configurations (docs/radiance-cache.md), at width 1
// (the integrator test checks that whole renders are bit-identical at widths 4 and 8): the
// hemisphere map, the masks' rows, rasterization, and reprojection of cache points built by
// an analytic ray caster -- a plane in front of the point, a box corner, and an occluder
// whose unseen side would leak the wall behind it without the unknown masks -- and the two
// ways a reprojection spread one texel of A's noise: a bright texel doubled or dropped by the
// nearest-texel lookup, and a wall A saw at grazing angles magnified.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#define PATINA_KERNEL_WIDTH 1
#include "render/cache/reprojection_impl.h"

using namespace patina;
using namespace patina::cache;

namespace {

// An axis-aligned rectangle: the plane x[axis] = at, the other two coordinates in [lo, hi];
// radiance a linear function of the hit point (value + slope . x), seen from either side.
struct Rect {
    int axis;
    float at;
    float lo[2], hi[2];
    float value[3];
    float slope[3] = {0, 0, 0};  // per unit of the hit's first free coordinate
};

struct Hit {
    float t = INFINITY;
    int rect = -1;
    Vec3f p{0, 0, 0}, n{0, 0, 0};
};

Hit cast(const std::vector<Rect>& scene, const Vec3f& o, const Vec3f& d) {
    Hit h;
    for (size_t r = 0; r < scene.size(); ++r) {
        const Rect& q = scene[r];
        const float oa[3] = {o.x, o.y, o.z}, da[3] = {d.x, d.y, d.z};
        if (da[q.axis] == 0) continue;
        const float t = (q.at - oa[q.axis]) / da[q.axis];
        if (!(t > 1e-6f) || t >= h.t) continue;
        float x[3];
        for (int k = 0; k < 3; ++k) x[k] = oa[k] + t * da[k];
        const int a1 = (q.axis + 1) % 3, a2 = (q.axis + 2) % 3;
        if (x[a1] < q.lo[0] || x[a1] > q.hi[0] || x[a2] < q.lo[1] || x[a2] > q.hi[1]) continue;
        h.t = t;
        h.rect = static_cast<int>(r);
        h.p = {x[0], x[1], x[2]};
        float n[3] = {0, 0, 0};
        n[q.axis] = da[q.axis] > 0 ? -1.0f : 1.0f;  // facing the ray's origin
        h.n = {n[0], n[1], n[2]};
    }
    return h;
}

void radiance_at(const Rect& q, const Vec3f& p, float* rgb) {
    const float x[3] = {p.x, p.y, p.z};
    const float u = x[(q.axis + 1) % 3];
    for (int k = 0; k < 3; ++k) rgb[k] = q.value[k] + q.slope[k] * u;
}

void frame_of(const Vec3f& n, Vec3f& t, Vec3f& b) {
    // any orthonormal frame (the tests do not depend on which)
    const Vec3f a = std::fabs(n.x) < 0.9f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0};
    t = normalize(cross(a, n));
    b = cross(n, t);
}

// A cache point at p with normal n built by casting a ray through each texel centre.
CachePoint build(const std::vector<Rect>& scene, const Vec3f& p, const Vec3f& n, int R) {
    CachePoint a;
    a.p = p, a.ng = n, a.n = n;
    frame_of(n, a.t, a.b);
    a.resolution = R;
    const size_t T = static_cast<size_t>(R) * R;
    a.radiance.assign(3 * T, 0.0f);
    a.dist.assign(T, INFINITY);
    a.kind.assign(T, kTexelMiss);
    a.hit_point.assign(3 * T, 0.0f);
    a.hit_normal.assign(3 * T, 0.0f);
    for (int j = 0; j < R; ++j)
        for (int i = 0; i < R; ++i) {
            const size_t k = static_cast<size_t>(j) * R + i;
            const Vec3f d = square_direction(a, (i + 0.5f) / R, (j + 0.5f) / R);
            const Hit h = cast(scene, p, d);
            if (h.rect < 0) continue;
            a.kind[k] = kTexelHit;
            a.dist[k] = h.t;
            store_vec3(h.p, a.hit_point.data() + 3 * k);
            store_vec3(h.n, a.hit_normal.data() + 3 * k);
            radiance_at(scene[h.rect], h.p, a.radiance.data() + 3 * k);
        }
    build_surfels(a);
    return a;
}

struct Result {
    Reprojection rep;
    std::vector<float> radiance;
    Receiver b;
    TexelDirections dirs;
};

Result reproject_into(const CachePoint& a, const Vec3f& p, const Vec3f& n, bool unknown_masks = true) {
    Result r;
    r.b.p = p, r.b.n = n;
    frame_of(n, r.b.t, r.b.b);
    r.dirs.prepare(a.resolution);
    r.radiance.assign(3 * a.resolution * a.resolution, -1.0f);
    ReprojectScratch rs;
    reproject(a, r.b, r.dirs, r.radiance.data(), r.rep, rs, unknown_masks);
    return r;
}

Vec3f texel_direction(const Result& r, int t) {
    return normalize(r.dirs.x[t] * r.b.t + r.dirs.y[t] * r.b.b + r.dirs.z[t] * r.b.n);
}

}  // namespace

TEST(CacheHemisphere, TheMapIsItsOwnInverseAndEqualArea) {
    const int R = 64;
    double z_sum = 0;
    for (int j = 0; j < R; ++j)
        for (int i = 0; i < R; ++i) {
            const float u = (i + 0.5f) / R, v = (j + 0.5f) / R;
            float x, y, z, u2, v2;
            square_to_hemisphere(u, v, x, y, z);
            EXPECT_NEAR(x * x + y * y + z * z, 1.0f, 2e-6f);
            EXPECT_GE(z, 0.0f);
            hemisphere_to_square(x, y, z, u2, v2);
            EXPECT_NEAR(u2, u, 2e-6f) << i << " " << j;
            EXPECT_NEAR(v2, v, 2e-6f) << i << " " << j;
            z_sum += z;
        }
    // equal solid angles: the texels' mean cosine is the hemisphere's, 1/2 (its integral / 2 pi)
    EXPECT_NEAR(z_sum / (R * R), 0.5, 1e-3);  // (the midpoint rule's error)
    // each texel's solid angle, summed over 8 x 8 sub-cells as spherical triangles: 2 pi / R^2
    const int r = 16, sub = 8;
    auto point = [&](double u, double v) {
        float x, y, z;
        square_to_hemisphere(static_cast<float>(u), static_cast<float>(v), x, y, z);
        return Vec3f{x, y, z};
    };
    auto tri = [](const Vec3f& a, const Vec3f& b, const Vec3f& c) {  // Van Oosterom-Strackee
        const double num = dot(a, cross(b, c));
        const double den = 1 + dot(a, b) + dot(b, c) + dot(c, a);
        return 2 * std::atan2(std::fabs(num), den);
    };
    for (int j = 0; j < r; ++j)
        for (int i = 0; i < r; ++i) {
            double omega = 0;
            for (int b = 0; b < sub; ++b)
                for (int a = 0; a < sub; ++a) {
                    const double u0 = (i + double(a) / sub) / r, u1 = (i + double(a + 1) / sub) / r;
                    const double v0 = (j + double(b) / sub) / r, v1 = (j + double(b + 1) / sub) / r;
                    const Vec3f c[4] = {point(u0, v0), point(u1, v0), point(u1, v1), point(u0, v1)};
                    omega += tri(c[0], c[1], c[2]) + tri(c[0], c[2], c[3]);
                }
            EXPECT_NEAR(omega, texel_solid_angle(r), 0.01 * texel_solid_angle(r)) << i << " " << j;
        }
    // below the horizon: outside the square, continuously
    float u, v;
    hemisphere_to_square(0.6f, 0.0f, -0.8f, u, v);
    EXPECT_GT(u, 1.0f);
    EXPECT_NEAR(v, 0.5f, 1e-6f);
}

TEST(CacheMasks, SpansAreTheRowBitsBetweenTheirEnds) {
    for (int a = 0; a <= 128; a += 7)
        for (int b = a; b <= 128; b += 5) {
            const Row128 r = span_bits(a, b);
            EXPECT_EQ(row_count(r), b - a);
            BitMask128 m;
            m.clear();
            m.rows[3] = r;
            for (int x = 0; x < 128; ++x) EXPECT_EQ(m.test(x, 3), x >= a && x < b) << a << " " << b << " " << x;
        }
    std::vector<int> seen;
    for_each_bit(span_bits(60, 70) | span_bits(127, 128), [&](int x) { seen.push_back(x); });
    ASSERT_EQ(seen.size(), 11u);
    EXPECT_EQ(seen.front(), 60);
    EXPECT_EQ(seen.back(), 127);
}

TEST(CacheRaster, AConvexRegionCoversTheTexelsWhoseCentresAreInside) {
    // a diamond given in scrambled order, with a point inside it that the hull drops
    const float px[5] = {10, 5, 10, 15, 10}, py[5] = {5, 10, 15, 10, 10};
    BitMask128 m;
    m.clear();
    raster_convex(px, py, 5, 32, [&](int y, Row128 span) { m.rows[y] |= span; });
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const float cx = x + 0.5f, cy = y + 0.5f;
            const bool inside = std::fabs(cx - 10) + std::fabs(cy - 10) < 5;
            const bool edge = std::fabs(std::fabs(cx - 10) + std::fabs(cy - 10) - 5) < 1e-4f;
            if (!edge) {
                EXPECT_EQ(m.test(x, y), inside) << x << " " << y;
            }
        }
    // clipped at the grid's border
    const float qx[4] = {-10, 40, 40, -10}, qy[4] = {-10, -10, 2, 2};
    m.clear();
    raster_convex(qx, qy, 4, 32, [&](int y, Row128 span) { m.rows[y] |= span; });
    EXPECT_EQ(m.count(32), 2 * 32);
}

// The hull as Andrew's monotone chain gives it after any sort by (x, y): the points sorted
// by index through std::sort, as the hull did before it sorted by rank.
int hull_by_sorted_indices(const float* px, const float* py, int n, float* hx, float* hy) {
    std::vector<int> order(n);
    for (int i = 0; i < n; ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](int a, int b) { return px[a] < px[b] || (px[a] == px[b] && py[a] < py[b]); });
    auto turn = [&](int o, int a, int b) {
        return (px[a] - px[o]) * (py[b] - py[o]) - (py[a] - py[o]) * (px[b] - px[o]);
    };
    int h[2 * kMaxHullPoints];
    int k = 0;
    for (int i = 0; i < n; ++i) {
        while (k >= 2 && turn(h[k - 2], h[k - 1], order[i]) <= 0) --k;
        h[k++] = order[i];
    }
    for (int i = n - 2, t = k + 1; i >= 0; --i) {
        while (k >= t && turn(h[k - 2], h[k - 1], order[i]) <= 0) --k;
        h[k++] = order[i];
    }
    const int m = std::max(k - 1, 0);
    for (int i = 0; i < m; ++i) hx[i] = px[h[i]], hy[i] = py[h[i]];
    return m;
}

// The sort by rank gives the hull the index sort gave, bit for bit: points on a coarse grid
// (ties in x, equal points, collinear runs) and points anywhere, 3 to 8 of them.
TEST(CacheRaster, TheHullIsTheSameWhateverTheSort) {
    uint32_t state = 12345u;
    auto next = [&]() {
        state = state * 1664525u + 1013904223u;
        return static_cast<float>(state >> 8) / 16777216.0f;
    };
    for (int trial = 0; trial < 4000; ++trial) {
        const int n = 3 + trial % 6;
        const bool coarse = trial % 2 == 0;
        float px[kMaxHullPoints], py[kMaxHullPoints];
        for (int i = 0; i < n; ++i) {
            px[i] = coarse ? std::floor(4 * next()) : 40 * next() - 4;
            py[i] = coarse ? std::floor(4 * next()) : 40 * next() - 4;
        }
        float ax[kMaxHullPoints], ay[kMaxHullPoints], bx[kMaxHullPoints], by[kMaxHullPoints];
        const int m = convex_hull(px, py, n, ax, ay);
        ASSERT_EQ(m, hull_by_sorted_indices(px, py, n, bx, by)) << trial;
        for (int i = 0; i < m; ++i) {
            EXPECT_EQ(ax[i], bx[i]) << trial << " " << i;
            EXPECT_EQ(ay[i], by[i]) << trial << " " << i;
        }
    }
}

// A plane facing the point, its radiance varying across it: a nearby point's hemisphere is
// reprojected wherever its rays meet the part of the plane A saw, with the plane's radiance
// there; where its rays go past the plane's edge, A's misses give zero or the texel is traced.
TEST(CacheReprojection, APlaneInFrontOfAPointReprojectsToItsRadiance) {
    const int R = 32;
    Rect plane{2, 1.0f, {-3, -3}, {3, 3}, {1.0f, 0.5f, 0.25f}, {0.2f, 0.1f, -0.05f}};
    const std::vector<Rect> scene{plane};
    const CachePoint a = build(scene, {0, 0, 0}, {0, 0, 1}, R);
    // one plane: merged surfels (but not across its depth layers)
    EXPECT_LT(a.surfels.size(), static_cast<size_t>(R * R) / 2);
    const Result r = reproject_into(a, {0.15f, -0.1f, 0.0f}, {0, 0, 1});
    int inside = 0, inside_filled = 0, wrong = 0;
    for (int t = 0; t < R * R; ++t) {
        const Vec3f d = texel_direction(r, t);
        const Hit h = cast(scene, r.b.p, d);
        const bool filled = r.rep.filled.test(t % R, t / R) && !r.rep.to_trace.test(t % R, t / R);
        if (h.rect >= 0 && std::fabs(h.p.x) < 2.5f && std::fabs(h.p.y) < 2.5f) {
            ++inside;
            if (!filled) continue;
            ++inside_filled;
            float expect[3];
            radiance_at(plane, h.p, expect);
            // nearest texel of A: the radiance changes by slope x A's texel footprint
            const float tol = 0.2f * 0.1f * h.t / std::max(std::fabs(d.z), 0.2f) + 1e-3f;
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.radiance[3 * t + k], expect[k], tol) << t;
        } else if (h.rect < 0 && filled) {
            for (int k = 0; k < 3; ++k) wrong += r.radiance[3 * t + k] != 0.0f;
        }
    }
    EXPECT_GT(inside, R * R / 2);
    EXPECT_GE(inside_filled, 0.97 * inside);  // holes only where surfels meet
    EXPECT_LE(wrong, R / 2);  // no plane radiance where B sees past it, but at the edge's texels
    EXPECT_EQ(r.rep.reprojected + r.rep.from_misses + r.rep.cracks + r.rep.traced, R * R);
}

// Inside a box's corner (three walls of different colours): a nearby point sees each wall
// where its rays meet it; texels where the walls meet may be traced, none takes a wrong wall.
TEST(CacheReprojection, ABoxCornerGivesEachTexelItsWall) {
    const int R = 32;
    const std::vector<Rect> scene{Rect{0, 1, {-4, -4}, {1, 1}, {1, 0, 0}}, Rect{1, 1, {-4, -4}, {1, 1}, {0, 1, 0}},
                                  Rect{2, 1, {-4, -4}, {1, 1}, {0, 0, 1}}};
    const Vec3f n = normalize(Vec3f{1, 1, 1});
    const CachePoint a = build(scene, {0, 0, 0}, n, R);
    const Result r = reproject_into(a, {0.08f, -0.05f, 0.03f}, n);
    int filled = 0, wrong = 0;
    for (int t = 0; t < R * R; ++t) {
        if (!r.rep.filled.test(t % R, t / R) || r.rep.to_trace.test(t % R, t / R)) continue;
        ++filled;
        const Hit h = cast(scene, r.b.p, texel_direction(r, t));
        ASSERT_GE(h.rect, 0);
        for (int k = 0; k < 3; ++k) wrong += r.radiance[3 * t + k] != scene[h.rect].value[k];
    }
    EXPECT_GE(filled, 0.9 * R * R);
    EXPECT_LE(wrong, 3 * R / 2);  // texel centres within rounding of a wall's edge
}

// A thin box in front of a wall, A straight in front of it: A sees the box's front and the
// wall around it, never the box's sides. From B, to the side, some rays meet the box's side
// just behind its front edge and would, without the unknown masks, take the wall radiance
// A saw beyond (a leak of light through the box). With them those texels are traced.
TEST(CacheReprojection, TheUnknownMaskStopsLightLeakingThroughAnOccluder) {
    const int R = 64;
    const float w = 0.05f, z0 = 0.3f, z1 = 0.9f;
    const std::vector<Rect> scene{
        Rect{2, 1.0f, {-4, -4}, {4, 4}, {1, 1, 1}},         // the wall, bright
        Rect{2, z0, {-w, -w}, {w, w}, {0.01f, 0.01f, 0.01f}},  // the box's front, dark
        Rect{0, w, {-w, z0}, {w, z1}, {0, 0, 0}},            // its sides, which A never sees
        Rect{0, -w, {-w, z0}, {w, z1}, {0, 0, 0}},
        Rect{1, w, {z0, -w}, {z1, w}, {0, 0, 0}},
        Rect{1, -w, {z0, -w}, {z1, w}, {0, 0, 0}},
    };
    const Vec3f n{0, 0, 1};
    const CachePoint a = build(scene, {0, 0, 0}, n, R);
    ASSERT_FALSE(a.silhouettes.empty());
    const Vec3f bp{0.3f, 0.0f, 0.0f};
    auto leaked = [&](const Result& r) {  // radiance taken by texels whose ray truly meets a side
        double sum = 0;
        int texels = 0;
        for (int t = 0; t < R * R; ++t) {
            const Hit h = cast(scene, r.b.p, texel_direction(r, t));
            if (h.rect < 2) continue;
            ++texels;
            if (r.rep.filled.test(t % R, t / R) && !r.rep.to_trace.test(t % R, t / R)) sum += r.radiance[3 * t];
        }
        EXPECT_GT(texels, 0);
        return sum;
    };
    const Result with = reproject_into(a, bp, n, true);
    const Result without = reproject_into(a, bp, n, false);
    EXPECT_EQ(leaked(with), 0.0);
    EXPECT_GT(leaked(without), 1.0);  // the configuration does leak without the masks
    // and the masks do not cost much elsewhere: most of the wall is still reprojected
    EXPECT_GT(with.rep.reprojected, 0.8 * without.rep.reprojected);
}

// A surfel B sees from behind is not reprojected: its texels are traced and hide what
// lies behind it.
TEST(CacheReprojection, ASurfelSeenFromBehindIsTracedAndHidesTheFarLayers) {
    const int R = 32;
    // a tilted panel: from A its front, from B (across its plane) its back
    const std::vector<Rect> scene{Rect{2, 2.0f, {-6, -6}, {6, 6}, {1, 1, 1}}, Rect{0, 0.5f, {-1, 0.2f}, {1, 1.5f}, {0.5f, 0, 0}}};
    const Vec3f n{0, 0, 1};
    const CachePoint a = build(scene, {0, 0, 0}, n, R);
    const Result r = reproject_into(a, {0.9f, 0, 0}, n);
    int behind = 0, through = 0;
    for (int t = 0; t < R * R; ++t) {
        const Hit h = cast(scene, r.b.p, texel_direction(r, t));
        if (h.rect != 1) continue;
        ++behind;
        const bool taken = r.rep.filled.test(t % R, t / R) && !r.rep.to_trace.test(t % R, t / R);
        through += taken && r.radiance[3 * t + 1] > 0;  // the wall's white through the panel
    }
    EXPECT_GT(behind, 40);
    EXPECT_LE(through, behind / 20);  // only at the panel's edge, within a texel
}

// Reprojected into a region (the second cache point, wanted in the first one's holes: the
// holes and their four neighbours), every texel of the holes ends as in the reprojection
// of the whole hemisphere: filled or to trace alike, the same radiance. Outside the region
// nothing is filled.
TEST(CacheReprojection, AReprojectionIntoARegionAgreesWithTheWholeOneInside) {
    const int R = 64;
    const float w = 0.05f, z0 = 0.3f, z1 = 0.9f;  // the occluder of the test above: shadows matter
    const std::vector<Rect> scene{
        Rect{2, 1.0f, {-4, -4}, {4, 4}, {1, 0.5f, 0.25f}, {0.3f, 0.2f, 0.1f}},
        Rect{2, z0, {-w, -w}, {w, w}, {0.01f, 0.01f, 0.01f}},
        Rect{0, w, {-w, z0}, {w, z1}, {0, 0, 0}},
        Rect{0, -w, {-w, z0}, {w, z1}, {0, 0, 0}},
        Rect{1, w, {z0, -w}, {z1, w}, {0, 0, 0}},
        Rect{1, -w, {z0, -w}, {z1, w}, {0, 0, 0}},
    };
    const Vec3f n{0, 0, 1};
    const CachePoint a = build(scene, {0, 0, 0}, n, R);
    const Result whole = reproject_into(a, {0.3f, 0.0f, 0.0f}, n);
    // wanted: every 7th texel (and, as fill_holes asks, its four neighbours)
    BitMask128 holes, region;
    holes.clear(), region.clear();
    for (int t = 0; t < R * R; t += 7) {
        const int x = t % R, y = t / R;
        holes.set(x, y);
        const int nb[5][2] = {{x, y}, {x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
        for (const auto& q : nb)
            if (q[0] >= 0 && q[1] >= 0 && q[0] < R && q[1] < R) region.set(q[0], q[1]);
    }
    Result part;
    part.b = whole.b;
    part.dirs.prepare(R);
    part.radiance.assign(3 * R * R, -1.0f);
    ReprojectScratch rs;
    reproject(a, part.b, part.dirs, part.radiance.data(), part.rep, rs, true, &region);
    int taken = 0;
    for (int y = 0; y < R; ++y)
        for (int x = 0; x < R; ++x) {
            if (!region.test(x, y)) {
                EXPECT_FALSE(part.rep.filled.test(x, y));
                continue;
            }
            if (!holes.test(x, y)) continue;
            ASSERT_EQ(part.rep.filled.test(x, y), whole.rep.filled.test(x, y)) << x << " " << y;
            ASSERT_EQ(part.rep.to_trace.test(x, y), whole.rep.to_trace.test(x, y)) << x << " " << y;
            if (!whole.rep.filled.test(x, y) || whole.rep.to_trace.test(x, y)) continue;
            ++taken;
            for (int k = 0; k < 3; ++k) EXPECT_EQ(part.radiance[3 * (y * R + x) + k], whole.radiance[3 * (y * R + x) + k]);
        }
    EXPECT_GT(taken, R * R / 14);  // most of the wanted texels were reprojected
}

// One bright texel of A (one path's catch) among dim ones, on a far plane, reprojected into
// points B shifted by fractions of a texel: B's texels take the bright texel's light in
// proportion to their overlap with it, never doubled or dropped whole (cache-room's light patch
// beside its corner, seed 1; with the nearest texel this test fails: at a shift of 0.098 the
// bright texel was dropped, none of its light in B).
TEST(CacheReprojection, ABrightTexelKeepsItsWeightWhateverTheShift) {
    const int R = 32;
    const float dim = 1.0f, bright = 100.0f;
    const std::vector<Rect> scene{Rect{2, 3.0f, {-20, -20}, {20, 20}, {dim, dim, dim}}};
    CachePoint a = build(scene, {0, 0, 0}, {0, 0, 1}, R);
    const int spike = 17 * R + 18;  // inside a 4 x 4 surfel of the plane, away from its edges
    for (int k = 0; k < 3; ++k) a.radiance[3 * spike + k] = bright;
    const float texel_on_plane = 3.0f * 2.5066283f / R;
    for (int step = 0; step < 12; ++step) {
        const float shift = texel_on_plane * step / 12.0f;
        const Result r = reproject_into(a, {shift, 0.37f * shift, 0.0f}, {0, 0, 1});
        double excess = 0;  // the bright texel's light in B, in texels of A's (equal solid angles)
        for (int t = 0; t < R * R; ++t)
            if (r.rep.filled.test(t % R, t / R) && !r.rep.to_trace.test(t % R, t / R))
                excess += (r.radiance[3 * t] - dim) / (bright - dim);
        EXPECT_NEAR(excess, 1.0, 0.25) << "shift " << shift;
    }
}

// A next to a wall sees it at grazing angles, a long strip per texel; B farther from the wall
// sees those strips head on, each over many of its texels. B traces the texels where one of
// A's would spread over more than kMaxMagnification of them (without the bound it took 52 such
// texels from A). The unknown masks are off: in this bare scene the wall's silhouettes at A's
// grazing angles (neighbouring hits more than 25 % apart) already send most of them to be
// traced, which in the room's corner they did not.
TEST(CacheReprojection, TexelsAMagnifiesAreTracedFromB) {
    const int R = 32;
    const std::vector<Rect> scene{Rect{0, -0.03f, {-6, -6}, {6, 6}, {1, 1, 1}}};  // the wall x = -0.03
    const Vec3f n{0, 0, 1};
    const CachePoint a = build(scene, {0, 0, 0}, n, R);
    const Result r = reproject_into(a, {0.27f, 0, 0}, n, false);
    int taken_magnified = 0, traced_magnified = 0;
    for (int t = 0; t < R * R; ++t) {
        const Vec3f d = texel_direction(r, t);
        const Hit h = cast(scene, r.b.p, d);
        if (h.rect < 0) continue;
        const Vec3f from_a = h.p - a.p;
        const float dist_a = std::sqrt(dot(from_a, from_a));
        const float cos_a = std::fabs(from_a.x) / dist_a, cos_b = std::fabs(d.x);
        const float magnification = dist_a * dist_a / (h.t * h.t) * cos_b / cos_a;
        if (magnification < 1.01f * kMaxMagnification) continue;  // the lookup's test, rounding aside
        const bool traced = r.rep.to_trace.test(t % R, t / R);
        const bool taken = r.rep.filled.test(t % R, t / R) && !traced;
        traced_magnified += traced;
        taken_magnified += taken;
    }
    EXPECT_GT(traced_magnified, R);
    EXPECT_EQ(taken_magnified, 0);
}
