// More paths where a cache point's light sits in a few texels (render/cache/concentrated_texels.h,
// refine_concentrated_texels in render/cache/radiance_cache_impl.h): a few planted bright texels
// (one lucky path each) are averaged toward the truth, a real small source is confirmed, light
// spread over neighbouring texels is left alone, and only `cache` refines.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#define PATINA_KERNEL_WIDTH 1
#include "render/cache/radiance_cache_impl.h"

using namespace patina;
using namespace patina::cache;

namespace {

constexpr int kR = 24;  // the cache's default resolution
// a bright texel: one path 120 times its neighbours, above kConcentration times them and the
// hemisphere's mean, below the fireflies' bound (kOutlierBound times its brightest neighbour)
constexpr float kSource = 120.0f;

// A cache point at the origin facing +z whose every texel saw radiance `level` (grey), one path each.
CachePoint flat_point(float level = 1.0f) {
    CachePoint a;
    a.p = Vec3f{0, 0, 0}, a.ng = a.n = Vec3f{0, 0, 1}, a.t = Vec3f{1, 0, 0}, a.b = Vec3f{0, 1, 0};
    a.resolution = kR;
    a.radiance.assign(3 * kR * kR, level);
    a.kind.assign(kR * kR, kTexelHit);
    return a;
}

void set_texel(CachePoint& a, int x, int y, float value) {
    for (int c = 0; c < 3; ++c) a.radiance[3 * (y * kR + x) + c] = value;
}
float texel_value(const CachePoint& a, int x, int y) { return a.radiance[3 * (y * kR + x)]; }

// The texel of the point's texture a world direction (in its frame: the world's) falls in.
int texel_of(const float* d) {
    float u, v;
    hemisphere_to_square(d[0], d[1], d[2], u, v);
    const int x = std::min(static_cast<int>(u * kR), kR - 1), y = std::min(static_cast<int>(v * kR), kR - 1);
    return y * kR + x;
}

// A tracer whose paths all return the truth: `bright` in the texel `source` (-1: none), 1 elsewhere.
struct TruthTracer {
    int source = -1;
    size_t rays = 0;
    void operator()(const float*, const float* d, const uint32_t*, const uint32_t*, size_t m, PathResult* out) {
        for (size_t r = 0; r < m; ++r) {
            const float L = texel_of(d + 3 * r) == source ? kSource : 1.0f;
            out[r] = PathResult{};
            for (int c = 0; c < 3; ++c) out[r].rgb[c] = L;
            out[r].depth = 1.0f;
        }
        rays += m;
    }
};

// Refines one point as a chunk of `cache` does; returns the paths traced.
size_t refine(CachePoint& a, TruthTracer& tracer, bool enabled = true) {
    CacheState cache;
    cache.texel_refinement.enabled = enabled;
    Query q;
    q.p = a.p, q.ng = a.ng, q.n = a.n, q.t = a.t, q.b = a.b, q.key = 7;
    const int32_t pending = 0;
    const auto texel = [&](int32_t where) { return a.radiance.data() + 3 * where; };  // one point: where is the texel
    refine_concentrated_texels(cache, tracer, &a, 1, &q, &pending, 1e-4f, texel);
    return tracer.rays;
}

double texture_error(const CachePoint& a, int source) {
    double error = 0;
    for (int t = 0; t < kR * kR; ++t) error += std::abs(a.radiance[3 * t] - (t == source ? kSource : 1.0f));
    return error;
}

}  // namespace

TEST(ConcentratedTexels, PlantedBrightTexelsAreAveragedTowardTheTruth) {
    CachePoint a = flat_point();
    const int planted[3][2] = {{3, 4}, {10, 2}, {12, 12}};  // lucky paths: the truth is 1 there
    for (const auto& p : planted) set_texel(a, p[0], p[1], kSource);
    const double before = texture_error(a, -1);
    TruthTracer tracer;
    const size_t rays = refine(a, tracer);
    // each planted texel and its eight neighbours take kStrata paths (none under the surface here)
    EXPECT_EQ(rays, static_cast<size_t>(3 * 9 * kStrata));
    // the planted texel is the mean of its lucky path and kStrata true ones
    for (const auto& p : planted)
        EXPECT_FLOAT_EQ(texel_value(a, p[0], p[1]), (kSource + kStrata) / (1 + kStrata));
    EXPECT_FLOAT_EQ(texel_value(a, 4, 4), 1.0f);  // a neighbour: all its paths agree
    EXPECT_LT(texture_error(a, -1), before / 4);
}

TEST(ConcentratedTexels, ARealSmallSourceIsConfirmed) {
    CachePoint a = flat_point();
    const int source = 5 * kR + 6;
    set_texel(a, 6, 5, kSource);
    TruthTracer tracer;
    tracer.source = source;
    EXPECT_GT(refine(a, tracer), 0u);
    // every stratum of the source's texel lies in it: it keeps its light, the neighbours theirs
    EXPECT_FLOAT_EQ(texel_value(a, 6, 5), kSource);
    EXPECT_FLOAT_EQ(texel_value(a, 7, 5), 1.0f);
    EXPECT_LT(texture_error(a, source), 1e-3);
}

TEST(ConcentratedTexels, LightSpreadOverNeighbouringTexelsIsLeftAlone) {
    CachePoint a = flat_point();
    for (int y = 6; y < 9; ++y)
        for (int x = 6; x < 9; ++x) set_texel(a, x, y, kSource);  // a lit patch: each texel has bright neighbours
    const std::vector<float> before = a.radiance;
    TruthTracer tracer;
    EXPECT_EQ(refine(a, tracer), 0u);
    EXPECT_EQ(a.radiance, before);
}

TEST(ConcentratedTexels, AtMostTheBrightestFewAPointAreRefined) {
    // a dark hemisphere with lit patches of 3 x 3 texels, a lucky path in the middle of each (so
    // the hemisphere's mean stays below their level over kConcentration)
    CachePoint a = flat_point(0.0f);
    const int planted = kMaxConcentrated + 2;
    for (int k = 0; k < planted; ++k) {
        const int x = 2 + 3 * k, y = 2 + (k % 2) * 8;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) set_texel(a, x + dx, y + dy, 1.0f);
        set_texel(a, x, y, kSource + k);
    }
    TruthTracer tracer;
    EXPECT_EQ(refine(a, tracer), static_cast<size_t>(kMaxConcentrated * 9 * kStrata));
    // the two dimmest planted texels keep their one path; the others are averaged
    EXPECT_FLOAT_EQ(texel_value(a, 2, 2), kSource);
    EXPECT_FLOAT_EQ(texel_value(a, 5, 10), kSource + 1);
    EXPECT_LT(texel_value(a, 8, 2), kSource / 2);
}

TEST(ConcentratedTexels, AFireflyAboveTheBoundIsLeftToTheBound) {
    // averaged here, a lucky path would lose more of its light than the bound takes from it
    CachePoint a = flat_point();
    set_texel(a, 9, 9, 2 * kOutlierBound);
    TruthTracer tracer;
    EXPECT_EQ(refine(a, tracer), 0u);
    EXPECT_FLOAT_EQ(texel_value(a, 9, 9), 2 * kOutlierBound);
}

TEST(ConcentratedTexels, OnlyTheCacheIntegratorRefines) {
    // cache-guided's guides need the light's shape only (mark_split_materials leaves it off)
    CachePoint a = flat_point();
    set_texel(a, 3, 4, kSource);
    TruthTracer tracer;
    EXPECT_EQ(refine(a, tracer, false), 0u);
    EXPECT_FLOAT_EQ(texel_value(a, 3, 4), kSource);
}

TEST(ConcentratedTexels, TexelsUnderTheSurfaceAreNotRefined) {
    // a bent shading normal: the rows nearest -y lie under the geometric surface and hold no light
    CachePoint a = flat_point();
    a.ng = normalize(Vec3f{0, 0.3f, 1});
    for (int t = 0; t < kR * kR; ++t) {
        float x, y, z;
        square_to_hemisphere((t % kR + 0.5f) / kR, (t / kR + 0.5f) / kR, x, y, z);
        if (dot(Vec3f{x, y, z}, a.ng) <= 0) a.kind[t] = kTexelBelow, set_texel(a, t % kR, t / kR, 0.0f);
    }
    // a texel above the surface beside texels under it, made bright
    int bright = -1;
    for (int t = 0; t < kR * kR && bright < 0; ++t)
        for (const int step : {-kR, -1, 1, kR})
            if (a.kind[t] == kTexelHit && t + step >= 0 && t + step < kR * kR && a.kind[t + step] == kTexelBelow)
                bright = t;
    ASSERT_GE(bright, 0);
    set_texel(a, bright % kR, bright / kR, kSource);
    const std::vector<uint8_t> kinds = a.kind;
    TruthTracer tracer;
    EXPECT_GT(refine(a, tracer), 0u);
    EXPECT_LT(a.radiance[3 * bright], kSource);
    for (int t = 0; t < kR * kR; ++t)
        if (kinds[t] == kTexelBelow) {
            ASSERT_EQ(a.radiance[3 * t], 0.0f) << "texel " << t;
        }
}
