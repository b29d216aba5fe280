// The cache integrators on a small closed box lit by a quad light (docs/radiance-cache.md):
// the same bits at widths 1, 4 and 8 and for any thread count, finite non-negative
// radiance, reuse of the cache points, and images whose mean agrees with the path tracer's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/cpu.h"
#include "render/accel/kdtree.h"
#include "render/cache/cache_settings.h"
#include "render/integrators/integrator.h"
#include "render/render_job.h"
#include "render/samplers/rng.h"
#include "render/scene.h"
#include "tests/cpp/render/cache/box_scene.h"

using namespace patina;
using namespace patina::test;

namespace {

std::vector<PathResult> trace(const BoxScene& b, int width, IntegratorMode mode, const std::vector<CameraSample>& cs,
                              PathScratch& sc, int block = 1, int hit_paths = CacheSettings{}.hit_paths) {
    IntegratorSettings st;
    st.max_depth = 4;
    st.mode = mode;
    st.cache.resolution = 16;
    st.cache.block = block;
    st.cache.hit_paths = hit_paths;
    st.cache.train_passes = 0;  // cache-guided: the cache points guide (the trained guide: tests/cpp/render/guiding)
    std::vector<PathResult> out(cs.size());
    render_kernels_for(width).trace_paths(b.scene, st, cs.data(), cs.size(), out.data(), sc);
    return out;
}

double mean_radiance(const std::vector<PathResult>& r) {
    double s = 0;
    for (const PathResult& p : r) s += p.rgb[0] + p.rgb[1] + p.rgb[2];
    return s / (3.0 * static_cast<double>(r.size()));
}

// The mean of the samples' radiance (RGB averaged) and the variance of that mean.
void moments(const std::vector<PathResult>& r, double& mean, double& var_of_mean) {
    double s = 0, s2 = 0;
    for (const PathResult& p : r) {
        const double x = (p.rgb[0] + p.rgb[1] + p.rgb[2]) / 3.0;
        s += x, s2 += x * x;
    }
    const double n = static_cast<double>(r.size());
    mean = s / n;
    var_of_mean = (s2 / n - mean * mean) / (n - 1);
}

RenderOptions job_settings(IntegratorMode mode, int threads, int spp, int width = 0) {
    RenderOptions st = box_job_settings(mode, threads, spp, width);
    st.max_pass_spp = 1;  // a pass a sample: the regions' cache points serve every pass
    st.cache.train_passes = 0;  // cache-guided: the cache points guide (the trained guide: tests/cpp/render/guiding)
    return st;
}

std::vector<float> render_job(const BoxScene& b, IntegratorMode mode, int threads, int spp, int width = 0,
                              size_t* cache_points = nullptr) {
    RenderJob job(b.scene, job_settings(mode, threads, spp, width));
    job.start();
    job.wait();
    if (cache_points) *cache_points = job.progress().cache_points;
    return resolved_rgb(b.scene, job);
}

}  // namespace

TEST(CacheIntegrators, WidthsFourAndEightGiveTheBitsOfWidthOne) {
    const BoxScene b(12, 12);
    const std::vector<CameraSample> cs = pixel_samples(12, 12, 2, 3);
    for (IntegratorMode mode : {IntegratorMode::Cache, IntegratorMode::CacheGuided})
    for (int block : {1, 4}) {
        PathScratch s1;
        const std::vector<PathResult> ref = trace(b, 1, mode, cs, s1, block);
        for (int width : {4, 8}) {
            if (!width_supported(width)) continue;
            PathScratch sw;
            const std::vector<PathResult> got = trace(b, width, mode, cs, sw, block);
            for (size_t i = 0; i < cs.size(); ++i)
                for (int k = 0; k < 3; ++k)
                    ASSERT_EQ(got[i].rgb[k], ref[i].rgb[k]) << "width " << width << " block " << block << " sample " << i;
            EXPECT_EQ(sw.cache_points, s1.cache_points);
            EXPECT_EQ(sw.rays_traced, s1.rays_traced);
        }
    }
}

TEST(CacheIntegrators, AnyThreadCountGivesTheSameImage) {
    const BoxScene b(16, 16);
    for (IntegratorMode mode : {IntegratorMode::Cache, IntegratorMode::CacheGuided}) {
        const std::vector<float> one = render_job(b, mode, 1, 2);
        const std::vector<float> three = render_job(b, mode, 3, 2);
        ASSERT_EQ(one.size(), three.size());
        for (size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i], three[i]) << i;
    }
}

// The render job's items start from the cache points of the image regions their tiles
// overlap (render/cache/cache_regions.h), built once each, whichever item and thread come
// first: the image is the same at every SIMD width and in any order of the tiles (here
// rendered one by one, last first, on the calling thread: a distributed render's way), and
// far fewer cache points are built than the items would build alone.
TEST(CacheIntegrators, SharedRegionsKeepTheImageIndependentOfWidthAndTileOrder) {
    const BoxScene b(40, 24);  // 2 x 1 regions of 32 pixels, 5 x 3 tiles of 8
    for (IntegratorMode mode : {IntegratorMode::Cache, IntegratorMode::CacheGuided}) {
        size_t points = 0;
        const std::vector<float> one = render_job(b, mode, 2, 3, 1, &points);
        for (int width : {4, 8}) {
            if (!width_supported(width)) continue;
            const std::vector<float> wide = render_job(b, mode, 2, 3, width);
            for (size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i], wide[i]) << "width " << width << ", " << i;
        }
        RenderJob job(b.scene, job_settings(mode, 1, 3, 1));
        size_t built = 0;
        for (int tile = job.tile_count() - 1; tile >= 0; --tile) built += job.render_tiles({tile}, 0, job.pass_count()).cache_points;
        const std::vector<float> reversed = resolved_rgb(b.scene, job);
        for (size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i], reversed[i]) << i;
        EXPECT_EQ(built, points);
        // each of the 15 tiles' 3 passes would place cache points of its own
        EXPECT_LT(points, 15u * 3u);
    }
}

// `cache` builds the regions again every generation of passes (render/cache/cache_generations.h),
// from numbers of the generation's own: with two generations the image is still the same at
// every SIMD width, for any thread count and in any order of the tiles, and the regions'
// cache points are built again (more points than one generation's).
TEST(CacheIntegrators, GenerationsKeepTheImageIndependentOfWidthThreadsAndTileOrder) {
    const BoxScene b(40, 24);  // 2 x 1 regions of 32 pixels
    auto settings = [](int threads, int spp, int width) {
        RenderOptions st = job_settings(IntegratorMode::Cache, threads, spp, width);
        st.max_pass_spp = 16;  // a generation a pass
        return st;
    };
    auto run = [&](int threads, int spp, int width, size_t* points) {
        RenderJob job(b.scene, settings(threads, spp, width));
        job.start();
        job.wait();
        if (points) *points = job.progress().cache_points;
        return resolved_rgb(b.scene, job);
    };
    size_t one_generation = 0, two = 0;
    run(1, 16, 1, &one_generation);
    const std::vector<float> image = run(1, 32, 1, &two);
    EXPECT_GT(two, one_generation);
    for (int width : {4, 8}) {
        if (!width_supported(width)) continue;
        const std::vector<float> wide = run(3, 32, width, nullptr);
        for (size_t i = 0; i < image.size(); ++i) ASSERT_EQ(image[i], wide[i]) << "width " << width << ", " << i;
    }
    RenderJob job(b.scene, settings(1, 32, 1));
    for (int tile = job.tile_count() - 1; tile >= 0; --tile) job.render_tiles({tile}, 0, job.pass_count());
    const std::vector<float> reversed = resolved_rgb(b.scene, job);
    for (size_t i = 0; i < image.size(); ++i) ASSERT_EQ(image[i], reversed[i]) << i;
}

// In a render of several passes the regions keep their queries' reconstructed hemispheres
// (render/cache/region_hemisphere.h) for every pass: the texels traced for 8 passes are far
// fewer than 8 passes reconstructing their own (what one pass traces, 8 times), and the
// image's mean stays the path tracer's within the stated bias.
TEST(CacheIntegrators, PassesShareTheRegionsReconstructions) {
    const BoxScene b(32, 32);
    auto run = [&](IntegratorMode mode, int spp, int pass_spp, size_t* traced) {
        RenderOptions st = job_settings(mode, 2, spp);
        st.max_pass_spp = pass_spp;
        RenderJob job(b.scene, st);
        job.start();
        job.wait();
        if (traced) *traced = job.progress().cache_texels_traced;
        double sum = 0;
        for (float v : resolved_rgb(b.scene, job)) sum += v;
        return sum;
    };
    size_t one = 0, eight = 0;
    run(IntegratorMode::Cache, 1, 1, &one);
    const double cached = run(IntegratorMode::Cache, 8, 1, &eight);
    EXPECT_GT(one, 0u);
    EXPECT_LT(eight, 3 * one);
    const double path = run(IntegratorMode::Path, 64, 16, nullptr);
    EXPECT_NEAR(cached / path, 1.0, 0.05);
}

TEST(CacheIntegrators, RadianceIsFiniteAndCachePointsAreReused) {
    const BoxScene b(16, 16);
    const std::vector<CameraSample> cs = pixel_samples(16, 16, 2, 9);
    for (IntegratorMode mode : {IntegratorMode::Cache, IntegratorMode::CacheGuided}) {
        PathScratch sc;
        const std::vector<PathResult> r = trace(b, 0, mode, cs, sc);
        for (const PathResult& p : r)
            for (int k = 0; k < 3; ++k) {
                ASSERT_TRUE(std::isfinite(p.rgb[k]));
                ASSERT_GE(p.rgb[k], 0.0f);
            }
        // a pixel's two samples share one query where they hit the same surface (most pixels)
        EXPECT_GT(sc.cache_queries, 0.45 * cs.size());
        EXPECT_LT(sc.cache_queries, 0.75 * cs.size());
        EXPECT_LT(sc.cache_points, sc.cache_queries / 2);
        if (mode == IntegratorMode::Cache) {
            EXPECT_GT(sc.cache_texels_reprojected, sc.cache_texels_traced);
        }
    }
}

// A worker builds region after region on one scratch: a region whose pixels make no query
// (here none at all; in a render, pixels that see only the sky or a light) has no cache
// points, not the last region's points left in the scratch after they were moved out (a
// tile reusing such an emptied point read its missing layers: a crash).
TEST(CacheIntegrators, ARegionWithoutQueriesHasNoCachePointsWhateverItsWorkerBuiltBefore) {
    const BoxScene b(16, 16);
    const std::vector<CameraSample> cs = pixel_samples(16, 16, 1, 4);
    for (IntegratorMode mode : {IntegratorMode::Cache, IntegratorMode::CacheGuided}) {
        IntegratorSettings st;
        st.max_depth = 4;
        st.mode = mode;
        st.cache.resolution = 16;
        st.cache.block = 4;
        PathScratch sc;
        std::vector<CachePoint> points;
        std::vector<RegionHemisphere> hemispheres;
        const RenderKernels& kernels = render_kernels_for(0);
        kernels.build_cache_region(b.scene, st, cs.data(), cs.size(), points, hemispheres, sc);
        ASSERT_FALSE(points.empty());
        for (const CachePoint& a : points) EXPECT_EQ(a.radiance.size(), 3u * 16 * 16);
        kernels.build_cache_region(b.scene, st, cs.data(), 0, points, hemispheres, sc);
        EXPECT_TRUE(points.empty());
        EXPECT_TRUE(hemispheres.empty());
    }
}

// Blocks of pixels share reconstructions: far fewer than one a pixel (in this small box the
// 0.3 R_A reach splits many of the 4 x 4 blocks, about 0.5 m across, once more), but never
// one across the box's walls, and an image whose mean is the per-pixel reconstruction's.
TEST(CacheIntegrators, BlocksOfPixelsShareReconstructionsButNotAcrossWalls) {
    const BoxScene b(16, 16);
    const std::vector<CameraSample> cs = pixel_samples(16, 16, 2, 21);
    PathScratch s1, s4;
    const double per_pixel = mean_radiance(trace(b, 0, IntegratorMode::Cache, cs, s1, 1));
    const std::vector<PathResult> r = trace(b, 0, IntegratorMode::Cache, cs, s4, 4);
    for (const PathResult& p : r)
        for (int k = 0; k < 3; ++k) ASSERT_TRUE(std::isfinite(p.rgb[k]) && p.rgb[k] >= 0.0f);
    EXPECT_LT(s4.cache_queries, s1.cache_queries / 3);
    // 16 blocks, and the blocks on a wall's edge (most of them here) hold two surfaces or more
    EXPECT_GT(s4.cache_queries, 16u + 8u);
    EXPECT_NEAR(mean_radiance(r) / per_pixel, 1.0, 0.04);
}

// A clear coat's lobe is narrower than any texel: `cache` builds no cache point for it but
// splits its first bounce into paths of its own BRDF sampling, an unbiased estimate: in a
// box of coated walls the image's mean is path's (a z-test of the two means against their
// standard errors: the near-mirror box's caustics make both noisy).
TEST(CacheIntegrators, ACoatIsPathTracedWithItsFirstBounceSplit) {
    BoxScene b(8, 8);
    for (Material& m : b.scene.materials)
        if (!m.is<Emitter>()) m.coat = ClearCoat{};
    PathScratch sp, sc;
    const std::vector<PathResult> path = trace(b, 0, IntegratorMode::Path, pixel_samples(8, 8, 512, 6), sp);
    const std::vector<PathResult> split = trace(b, 0, IntegratorMode::Cache, pixel_samples(8, 8, 128, 7), sc);
    EXPECT_EQ(sc.cache_queries, 0u);
    EXPECT_EQ(sc.cache_points, 0u);
    for (const PathResult& p : split)
        for (int k = 0; k < 3; ++k) ASSERT_TRUE(std::isfinite(p.rgb[k]) && p.rgb[k] >= 0.0f);
    double mp, vp, ms, vs;
    moments(path, mp, vp);
    moments(split, ms, vs);
    EXPECT_LT(std::abs(ms - mp) / std::sqrt(vp + vs), 4.0) << "path " << mp << ", split " << ms;
    EXPECT_LT(vs * static_cast<double>(split.size()), vp * static_cast<double>(path.size()));  // less noise a sample
}

// A lobe between half a texel and two texels wide (a glossy floor: box_scene.h's `narrow`,
// GGX 0.25 at R = 16) is left to the path tracer with its first bounce one path of its own
// BRDF sampling (the texture's lookup had 1.8 times path's error on the room's floor):
// `cache` builds no query for it, keeps path's mean (a z-test), and gives width 1's bits at
// widths 4, 8 and 16 and the same image on any thread count.
TEST(CacheIntegrators, ALobeTheTexelsCannotResolveIsPathTracedWithOnePath) {
    BoxScene b(8, 8);
    for (Material& m : b.scene.materials)
        if (!m.is<Emitter>()) m.model = metal(0.25f);
    PathScratch sp, sc;
    const std::vector<PathResult> path = trace(b, 0, IntegratorMode::Path, pixel_samples(8, 8, 512, 6), sp);
    const std::vector<PathResult> cached = trace(b, 1, IntegratorMode::Cache, pixel_samples(8, 8, 128, 7), sc);
    EXPECT_EQ(sc.cache_queries, 0u);
    double mp, vp, mc, vc;
    moments(path, mp, vp);
    moments(cached, mc, vc);
    EXPECT_LT(std::abs(mc - mp) / std::sqrt(vp + vc), 4.0) << "path " << mp << ", cache " << mc;
    const std::vector<CameraSample> few = pixel_samples(8, 8, 2, 3);
    PathScratch r1;
    const std::vector<PathResult> ref = trace(b, 1, IntegratorMode::Cache, few, r1);
    for (int width : {4, 8, 16}) {
        if (!width_supported(width)) continue;
        PathScratch sw;
        const std::vector<PathResult> got = trace(b, width, IntegratorMode::Cache, few, sw);
        for (size_t i = 0; i < few.size(); ++i)
            for (int k = 0; k < 3; ++k) ASSERT_EQ(got[i].rgb[k], ref[i].rgb[k]) << "width " << width << " sample " << i;
    }
    EXPECT_EQ(render_job(b, IntegratorMode::Cache, 1, 4), render_job(b, IntegratorMode::Cache, 3, 4));
}

// Direct light alone (max_depth 1): the cache has nothing to do, the image is the path
// tracer's bit for bit.
TEST(CacheIntegrators, DirectLightingIsThePathTracers) {
    const BoxScene b(8, 8);
    const std::vector<CameraSample> cs = pixel_samples(8, 8, 1, 1);
    IntegratorSettings st;
    st.max_depth = 1;
    std::vector<PathResult> path(cs.size()), cached(cs.size());
    PathScratch s1, s2;
    render_kernels_for(0).trace_paths(b.scene, st, cs.data(), cs.size(), path.data(), s1);
    st.mode = IntegratorMode::Cache;
    render_kernels_for(0).trace_paths(b.scene, st, cs.data(), cs.size(), cached.data(), s2);
    for (size_t i = 0; i < cs.size(); ++i)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(path[i].rgb[k], cached[i].rgb[k]);
}

// The image's mean (the box's light, bounced up to three times) against the path tracer's
// with many samples: cache-guided is unbiased, cache within its reprojection's bias.
TEST(CacheIntegrators, TheMeanRadianceAgreesWithThePathTracers) {
    const BoxScene b(16, 16);
    PathScratch sp, sc, sg;
    const double path = mean_radiance(trace(b, 0, IntegratorMode::Path, pixel_samples(16, 16, 256, 11), sp));
    const double cache = mean_radiance(trace(b, 0, IntegratorMode::Cache, pixel_samples(16, 16, 4, 12), sc));
    const double guided = mean_radiance(trace(b, 0, IntegratorMode::CacheGuided, pixel_samples(16, 16, 64, 13), sg));
    EXPECT_NEAR(cache / path, 1.0, 0.05);
    EXPECT_NEAR(guided / path, 1.0, 0.03);
}

// cache-guided draws first bounces from the cache points' guides (render/cache/guided_*):
// with the same camera samples its image is not the path tracer's, and a render through the
// job, whose items take the regions' points, agrees with path in the mean (a z-test of the
// two images' means against their pixels' scatter).
TEST(CacheIntegrators, CacheGuidedDrawsFromTheGuidesAndKeepsThePathTracersMean) {
    const BoxScene b(16, 16);
    const std::vector<CameraSample> cs = pixel_samples(16, 16, 4, 17);
    PathScratch sp, sg;
    const std::vector<PathResult> path = trace(b, 0, IntegratorMode::Path, cs, sp);
    const std::vector<PathResult> guided = trace(b, 0, IntegratorMode::CacheGuided, cs, sg);
    EXPECT_GT(sg.cache_points, 0u);
    size_t differ = 0;
    for (size_t i = 0; i < cs.size(); ++i) differ += path[i].rgb[0] != guided[i].rgb[0];
    EXPECT_GT(differ, cs.size() / 4);
    const std::vector<float> a = render_job(b, IntegratorMode::Path, 2, 32);
    const std::vector<float> g = render_job(b, IntegratorMode::CacheGuided, 2, 32);
    double sum = 0, sum2 = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        const double d = static_cast<double>(g[i]) - a[i];
        sum += d, sum2 += d * d;
    }
    const double n = static_cast<double>(a.size()), mean = sum / n;
    const double se = std::sqrt((sum2 / n - mean * mean) / (n - 1));
    EXPECT_LT(std::abs(mean) / se, 4.0) << mean;
}

// A cache point's texel whose hit is on a glossy surface (a lobe the texels do not resolve)
// takes cache.hit_paths paths from that hit (render/cache/radiance_cache_impl.h,
// split_glossy_hits), their mean its light: a box with a glossy floor keeps the path
// tracer's mean within the stated bias with 1 and with 4 paths, the 4 cost rays at the
// glossy hits only (not four paths a texel), and widths give the same bits.
TEST(CacheIntegrators, GlossyTexelHitsKeepTheMeanAndTheBitsOfWidthOne) {
    const BoxScene b(12, 12, true);
    PathScratch sp, s1, s4;
    const double path = mean_radiance(trace(b, 0, IntegratorMode::Path, pixel_samples(12, 12, 512, 21), sp));
    const std::vector<CameraSample> cs = pixel_samples(12, 12, 8, 22);
    const double one = mean_radiance(trace(b, 0, IntegratorMode::Cache, cs, s1, 4, 1));
    const double four = mean_radiance(trace(b, 0, IntegratorMode::Cache, cs, s4, 4, 4));
    EXPECT_NEAR(four / path, 1.0, 0.05);
    EXPECT_NEAR(one / path, 1.0, 0.05);
    EXPECT_GT(s4.rays_traced, s1.rays_traced);
    EXPECT_LT(s4.rays_traced, 2 * s1.rays_traced);
    const std::vector<CameraSample> few = pixel_samples(12, 12, 2, 3);
    PathScratch r1;
    const std::vector<PathResult> ref = trace(b, 1, IntegratorMode::Cache, few, r1, 4, 4);
    for (int width : {4, 8, 16}) {
        if (!width_supported(width)) continue;
        PathScratch sw;
        const std::vector<PathResult> got = trace(b, width, IntegratorMode::Cache, few, sw, 4, 4);
        for (size_t i = 0; i < few.size(); ++i)
            for (int k = 0; k < 3; ++k) {
                ASSERT_EQ(got[i].rgb[k], ref[i].rgb[k]) << "width " << width << " sample " << i;
                ASSERT_TRUE(std::isfinite(got[i].rgb[k]) && got[i].rgb[k] >= 0);
            }
    }
}

TEST(CacheIntegrators, HitPathsOutOfRangeNameTheKey) {
    for (int bad : {0, 17}) {
        CacheSettings s;
        s.hit_paths = bad;
        try {
            check_cache_settings(s);
            FAIL() << "hit_paths " << bad << " accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find("cache.hit_paths"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("1 to 16"), std::string::npos) << e.what();
        }
    }
}
