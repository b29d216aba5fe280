// cache-guided with its trained guide (render/guiding/guide_training.h) in the render job, on
// the cache tests' lit box: the training records the paths' vertices and builds a field; the
// image is the same for 1 and 2 threads, at widths 1, 8 and 16 and with the tiles rendered
// one by one in reverse order (a distributed render's way); it draws from the guide (not the
// path tracer's image) and agrees with the path tracer's in the mean (a z-test), with finite,
// non-negative radiance.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/cpu.h"
#include "render/cache/cache_settings.h"
#include "render/guiding/guide_training.h"
#include "render/render_job.h"
#include "tests/cpp/render/cache/box_scene.h"

using namespace patina;
using namespace patina::test;

namespace {

RenderOptions trained(IntegratorMode mode, int threads, int spp, int width = 0) {
    RenderOptions st = box_job_settings(mode, threads, spp, width);
    st.max_depth = 6;
    st.cache.train_passes = 2;
    st.cache.train_bounces = 16;  // every bounce
    st.cache.train_spp = 2;
    return st;
}

}  // namespace

TEST(TrainedGuide, TrainingRecordsTheVerticesAndBuildsAField) {
    const BoxScene b(24, 24);
    IntegratorSettings st;
    st.max_depth = 5;
    st.mode = IntegratorMode::CacheGuided;
    st.cache.train_passes = 2;
    guiding::GuideTraining training(b.scene, st, render_kernels_for(0), 3);
    PathScratch sc;
    training.take_part(sc);
    EXPECT_TRUE(training.trained());
    // 24 x 24 pixels, 2 passes of 1 path: more than one record a path (the box is closed)
    EXPECT_GT(training.records(), 2u * 24 * 24);
    EXPECT_FALSE(training.field().empty());
    EXPECT_EQ(sc.guide_field, nullptr);  // the scratch as it was
    EXPECT_EQ(sc.guide_sink, nullptr);
}

TEST(TrainedGuide, TheImageIsTheSameForThreadsWidthsAndTileOrder) {
    const BoxScene b(24, 16);
    const std::vector<float> one = rendered_rgb(b.scene, trained(IntegratorMode::CacheGuided, 1, 4, 1));
    const std::vector<float> two = rendered_rgb(b.scene, trained(IntegratorMode::CacheGuided, 2, 4, 1));
    for (size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i], two[i]) << i;
    for (int width : {8, 16}) {
        if (!width_supported(width)) continue;
        const std::vector<float> wide = rendered_rgb(b.scene, trained(IntegratorMode::CacheGuided, 2, 4, width));
        for (size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i], wide[i]) << "width " << width << ", " << i;
    }
    RenderJob job(b.scene, trained(IntegratorMode::CacheGuided, 1, 4, 1));
    for (int tile = job.tile_count() - 1; tile >= 0; --tile) job.render_tiles({tile}, 0, job.pass_count());
    const std::vector<float> rgb = resolved_rgb(b.scene, job);
    for (size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i], rgb[i]) << i;
}

TEST(TrainedGuide, DrawsFromTheGuideAndKeepsThePathTracersMean) {
    const BoxScene b(16, 16);
    const std::vector<float> path = rendered_rgb(b.scene, trained(IntegratorMode::Path, 2, 32));
    const std::vector<float> guided = rendered_rgb(b.scene, trained(IntegratorMode::CacheGuided, 2, 32));
    size_t differ = 0;
    double sum = 0, sum2 = 0;
    for (size_t i = 0; i < path.size(); ++i) {
        ASSERT_TRUE(std::isfinite(guided[i]) && guided[i] >= 0) << i;
        differ += path[i] != guided[i];
        const double d = static_cast<double>(guided[i]) - path[i];
        sum += d, sum2 += d * d;
    }
    EXPECT_GT(differ, path.size() / 2);
    const double n = static_cast<double>(path.size()), mean = sum / n;
    const double se = std::sqrt((sum2 / n - mean * mean) / (n - 1));
    EXPECT_LT(std::abs(mean) / se, 4.0) << mean;
}

// cache.train_max_depth (the low-level binding's measuring knob): a render cut to direct light
// (max_depth 2) samples the guide trained on paths of 5 vertices, so its first vertex is the
// full render's -- the cut image is the full one's first part, below it in every pixel -- and
// not the path tracer's direct light (the guide draws some first bounces that hit the light).
TEST(TrainedGuide, ACutRenderSamplesTheGuideTrainedOnFullPaths) {
    const BoxScene b(16, 16);
    RenderOptions cut = trained(IntegratorMode::CacheGuided, 2, 8);
    cut.cache.train_bounces = 1;
    RenderOptions full = cut;
    cut.max_depth = 2;
    cut.cache.train_max_depth = full.max_depth;
    RenderOptions untrained = cut;
    untrained.cache.train_max_depth = 0;  // trained on the cut paths: no indirect records, no guide
    const std::vector<float> first = rendered_rgb(b.scene, cut), whole = rendered_rgb(b.scene, full);
    const std::vector<float> direct = rendered_rgb(b.scene, untrained);
    size_t differ = 0;
    for (size_t i = 0; i < first.size(); ++i) {
        ASSERT_LE(first[i], whole[i] + 1e-5f * whole[i]) << i;
        differ += first[i] != direct[i];
    }
    EXPECT_GT(differ, 0u);
}

TEST(TrainedGuide, TrainMaxDepthOutOfRangeNamesTheSetting) {
    for (int bad : {-1, 1025}) {
        CacheSettings s;
        s.train_max_depth = bad;
        try {
            check_cache_settings(s);
            FAIL() << "train_max_depth " << bad << " accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find("cache.train_max_depth"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("0 to 1024"), std::string::npos) << e.what();
        }
    }
}
