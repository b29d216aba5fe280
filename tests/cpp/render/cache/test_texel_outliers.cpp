// The bound on a hemisphere's isolated bright texels (render/cache/texel_outliers.h): one
// texel holding a firefly no longer carries the hemisphere's light (the blotch every point
// reusing it would show), while light spread over neighbouring texels -- a sunlit patch --
// keeps every texel and so its energy.
#include <gtest/gtest.h>

#include <vector>

#define PATINA_KERNEL_WIDTH 1
#include "render/cache/texel_outliers.h"

using namespace patina;
using namespace patina::cache;

namespace {

constexpr int kR = 24;

// A smooth hemisphere: radiance from 1 to 2 across the rows, grey.
std::vector<float> smooth_texture() {
    std::vector<float> radiance(3 * kR * kR);
    for (int y = 0; y < kR; ++y)
        for (int x = 0; x < kR; ++x)
            for (int c = 0; c < 3; ++c) radiance[3 * (y * kR + x) + c] = 1.0f + static_cast<float>(y) / kR;
    return radiance;
}

double total_light(const std::vector<float>& radiance) {
    double sum = 0;
    for (const float v : radiance) sum += v;
    return sum;
}

float* texel(std::vector<float>& radiance, int x, int y) { return radiance.data() + 3 * (y * kR + x); }

}  // namespace

TEST(TexelOutliers, OneFireflyTexelNoLongerCarriesTheHemispheresLight) {
    const std::vector<float> clean = smooth_texture();
    std::vector<float> radiance = clean;
    // one path that found the sun: 10^5 times its neighbours, a red-tinted sample
    float* firefly = texel(radiance, 7, 11);
    firefly[0] = 2.0e5f, firefly[1] = 1.0e5f, firefly[2] = 1.0e5f;
    const double with_firefly = total_light(radiance);
    std::vector<float> luminances;
    EXPECT_EQ(bound_isolated_texels(radiance.data(), kR, luminances), 1);
    // the firefly held 98 % of the hemisphere's light, the light every point reusing it
    // integrates; bounded by its brightest neighbour (row 12), the hemisphere carries what
    // the clean one does but for the bound's share (a quarter more here: 128 x one texel)
    EXPECT_GT(with_firefly, 50 * total_light(clean));
    EXPECT_LT(total_light(radiance), 1.3 * total_light(clean));
    const float brightest_neighbour = 1.0f + 12.0f / kR;
    EXPECT_NEAR(luminance(firefly), kOutlierBound * brightest_neighbour, 1e-4f * kOutlierBound);
    EXPECT_FLOAT_EQ(firefly[0], 2 * firefly[1]);  // its colour kept
    EXPECT_FLOAT_EQ(firefly[1], firefly[2]);
    for (int t = 0; t < kR * kR; ++t) {  // every other texel as it was
        if (t == 11 * kR + 7) continue;
        for (int c = 0; c < 3; ++c) ASSERT_EQ(radiance[3 * t + c], clean[3 * t + c]) << "texel " << t;
    }
}

TEST(TexelOutliers, AFireflyAmongBrightNeighboursIsBoundedByTheBrightest) {
    // a hemisphere lit by a bright wall in part: the other texels' mean is below the
    // neighbours' level, so the brightest neighbour sets the bound
    std::vector<float> radiance(3 * kR * kR, 0.0f);
    for (int y = 8; y < 16; ++y)
        for (int x = 8; x < 16; ++x)
            for (int c = 0; c < 3; ++c) texel(radiance, x, y)[c] = x == 9 && y == 12 ? 40.0f : 10.0f;
    float* firefly = texel(radiance, 10, 12);
    for (int c = 0; c < 3; ++c) firefly[c] = 1.0e4f;  // 1000 times the wall
    std::vector<float> luminances;
    EXPECT_EQ(bound_isolated_texels(radiance.data(), kR, luminances), 1);
    EXPECT_NEAR(luminance(firefly), kOutlierBound * 40.0f, 1e-3f * kOutlierBound * 40.0f);
}

TEST(TexelOutliers, LightSpreadOverNeighbouringTexelsIsKept) {
    std::vector<float> radiance = smooth_texture();
    // a sunlit patch of 2 x 2 texels, each 10^4 times the rest: each has a bright neighbour
    for (int y = 5; y < 7; ++y)
        for (int x = 9; x < 11; ++x)
            for (int c = 0; c < 3; ++c) texel(radiance, x, y)[c] = 1.0e4f;
    const std::vector<float> before = radiance;
    std::vector<float> luminances;
    EXPECT_EQ(bound_isolated_texels(radiance.data(), kR, luminances), 0);
    EXPECT_EQ(radiance, before);
}

TEST(TexelOutliers, AFireflyInADarkHemisphereIsBoundedByTheOtherTexelsMean) {
    // misses and texels under the surface hold no light: a firefly among them is bounded by
    // the mean of the other texels (not its own, which would grow with it), not by its black
    // neighbours to nothing
    std::vector<float> radiance(3 * kR * kR, 0.0f);
    for (int x = 0; x < kR; ++x)
        for (int c = 0; c < 3; ++c) texel(radiance, x, kR - 1)[c] = 1.0f;  // one lit row at the horizon
    const float others_mean = static_cast<float>(kR) / (kR * kR - 1);
    float* firefly = texel(radiance, 12, 3);
    for (int c = 0; c < 3; ++c) firefly[c] = 1.0e6f;
    std::vector<float> luminances;
    EXPECT_EQ(bound_isolated_texels(radiance.data(), kR, luminances), 1);
    EXPECT_NEAR(luminance(firefly), kOutlierBound * others_mean, 1e-3f * kOutlierBound * others_mean);
}

TEST(TexelOutliers, BoundsAreTakenFromTheTextureAsItWas) {
    // two fireflies side by side are each other's bright neighbour: light concentrated in two
    // texels is kept, whichever is visited first
    std::vector<float> radiance = smooth_texture();
    for (int c = 0; c < 3; ++c) texel(radiance, 3, 3)[c] = texel(radiance, 4, 3)[c] = 1.0e5f;
    std::vector<float> luminances;
    EXPECT_EQ(bound_isolated_texels(radiance.data(), kR, luminances), 0);
    EXPECT_EQ(texel(radiance, 3, 3)[0], 1.0e5f);
}
