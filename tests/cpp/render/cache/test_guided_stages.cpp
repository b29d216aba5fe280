// cache-guided's stages (render/cache/guided_stages_impl.h) with the cache points guiding
// every bounce (cache.guide_bounces, docs/radiance-cache.md "Guiding every bounce"), on the
// closed box lit by a quad light: the later bounces draw from the guides (the image is not the
// first-bounce guide's), every width gives the bits of width 1 lane by lane, any thread count
// the same image, and the image's mean is the path tracer's (the mixture's density is exact).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/cpu.h"
#include "render/integrators/integrator.h"
#include "render/render_job.h"
#include "tests/cpp/render/cache/box_scene.h"

using namespace patina;
using namespace patina::test;

namespace {

constexpr int kEveryBounce = 16;  // more than the box's paths have (max_depth 4 or 5)

std::vector<PathResult> trace(const BoxScene& b, int width, IntegratorMode mode, const std::vector<CameraSample>& cs,
                              int guide_bounces) {
    IntegratorSettings st;
    st.max_depth = 4;
    st.mode = mode;
    st.cache.resolution = 16;
    st.cache.train_passes = 0;  // the cache points guide
    st.cache.guide_bounces = guide_bounces;
    std::vector<PathResult> out(cs.size());
    PathScratch scratch;
    render_kernels_for(width).trace_paths(b.scene, st, cs.data(), cs.size(), out.data(), scratch);
    return out;
}

std::vector<float> render_job(const BoxScene& b, IntegratorMode mode, int threads, int spp, int width, float guide) {
    RenderOptions st = box_job_settings(mode, threads, spp, width);
    st.max_pass_spp = 1;
    st.cache.train_passes = 0;
    st.cache.guide_bounces = kEveryBounce;
    st.cache.guide = guide;
    return rendered_rgb(b.scene, st);
}

// |mean of a - b| over its standard error, over the images' pixels and channels.
double z_of_difference(const std::vector<float>& a, const std::vector<float>& b) {
    double sum = 0, sum2 = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        const double d = static_cast<double>(a[i]) - b[i];
        sum += d, sum2 += d * d;
    }
    const double n = static_cast<double>(a.size()), mean = sum / n;
    return std::abs(mean) / std::sqrt((sum2 / n - mean * mean) / (n - 1));
}

}  // namespace

TEST(GuidedStages, EveryBounceDrawsLaterBouncesFromTheCachePoints) {
    const BoxScene b(12, 12);
    const std::vector<CameraSample> cs = pixel_samples(12, 12, 4, 21);
    const std::vector<PathResult> first = trace(b, 1, IntegratorMode::CacheGuided, cs, 1);
    const std::vector<PathResult> every = trace(b, 1, IntegratorMode::CacheGuided, cs, kEveryBounce);
    size_t differ = 0;
    for (size_t i = 0; i < cs.size(); ++i) differ += first[i].rgb[0] != every[i].rgb[0];
    EXPECT_GT(differ, cs.size() / 4);
}

TEST(GuidedStages, EveryBounceGivesTheBitsOfWidthOneInEveryLane) {
    const BoxScene b(12, 12);
    const std::vector<CameraSample> cs = pixel_samples(12, 12, 2, 3);
    const std::vector<PathResult> scalar = trace(b, 1, IntegratorMode::CacheGuided, cs, kEveryBounce);
    for (int width : {4, 8, 16}) {
        if (!width_supported(width)) continue;
        const std::vector<PathResult> wide = trace(b, width, IntegratorMode::CacheGuided, cs, kEveryBounce);
        for (size_t i = 0; i < cs.size(); ++i)
            for (int k = 0; k < 3; ++k) ASSERT_EQ(wide[i].rgb[k], scalar[i].rgb[k]) << "width " << width << " sample " << i;
    }
}

TEST(GuidedStages, EveryBounceGivesTheSameImageForAnyThreadCount) {
    const BoxScene b(16, 16);
    const std::vector<float> one = render_job(b, IntegratorMode::CacheGuided, 1, 2, 0, 0.5f);
    const std::vector<float> three = render_job(b, IntegratorMode::CacheGuided, 3, 2, 0, 0.5f);
    for (size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i], three[i]) << i;
}

// A z-test of the image's mean against the path tracer's (both 32 spp), at the default guide
// probability and at 0.9, where a density the mixture got wrong would weigh most.
TEST(GuidedStages, EveryBounceKeepsThePathTracersMean) {
    const BoxScene b(16, 16);
    const std::vector<float> path = render_job(b, IntegratorMode::Path, 2, 32, 0, 0.5f);
    for (float guide : {0.5f, 0.9f}) {
        const std::vector<float> guided = render_job(b, IntegratorMode::CacheGuided, 2, 32, 0, guide);
        EXPECT_LT(z_of_difference(guided, path), 4.0) << "guide " << guide;
    }
}
