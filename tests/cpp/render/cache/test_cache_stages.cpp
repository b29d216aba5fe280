// The cache stages' pixel bookkeeping (render/cache/cache_stages_impl.h): which pixel a camera
// sample lies in -- the adaptive sampler's corners on the image's right and bottom edges
// included, which lie at x = width or y = height and belong to the last column or row (taken
// as x = width they named the next row's first pixel, and drew its hemisphere) -- and the
// regions and blocks of those pixels.
#include <gtest/gtest.h>

#define PATINA_KERNEL_WIDTH 1
#include "render/cache/cache_stages_impl.h"

using namespace patina;
using namespace patina::cache;

namespace {

SamplePixel at(const Camera& cam, float x, float y) { return pixel_of_sample(cam, CameraSample{x, y, 0, 0}); }

}  // namespace

TEST(CacheStages, ASampleIsInThePixelItsFilmCoordinatesFloorTo) {
    Camera cam;
    cam.width = 70, cam.height = 40;
    const SamplePixel inside = at(cam, 10.5f, 7.25f);
    EXPECT_EQ(inside.x, 10);
    EXPECT_EQ(inside.y, 7);
    const SamplePixel corner = at(cam, 0.0f, 0.0f);
    EXPECT_EQ(corner.x, 0);
    EXPECT_EQ(corner.y, 0);
}

TEST(CacheStages, CornersOnTheRightAndBottomEdgesAreInTheLastColumnAndRow) {
    Camera cam;
    cam.width = 70, cam.height = 40;
    const SamplePixel right = at(cam, 70.0f, 12.0f), bottom = at(cam, 33.0f, 40.0f), both = at(cam, 70.0f, 40.0f);
    EXPECT_EQ(right.x, 69);
    EXPECT_EQ(right.y, 12);
    EXPECT_EQ(bottom.x, 33);
    EXPECT_EQ(bottom.y, 39);
    EXPECT_EQ(both.x, 69);
    EXPECT_EQ(both.y, 39);
    // so their region and block are the last column's and row's, inside the image
    EXPECT_EQ(region_of_pixel(cam, right.x, right.y), region_of_pixel(cam, 69, 12));
    EXPECT_LT(region_of_pixel(cam, both.x, both.y), 3 * 2);  // 3 x 2 regions of 32 pixels
    EXPECT_EQ(block_of_pixel(cam, 8, both.x, both.y), (39 / 8) * 9 + 69 / 8);
}
