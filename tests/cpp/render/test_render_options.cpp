// The render options' one range table: each option out of range is refused by name, with its
// range, and a float option is compared as the float it arrives as.
#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>

#include "render/integrators/integrator.h"
#include "render/render_options.h"

using namespace patina;

namespace {

// The message check_render_options gives for `options`, or "" when it accepts them.
std::string refusal(const RenderOptions& options) {
    try {
        check_render_options(options);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(RenderOptions, TheDefaultsAreInRange) { EXPECT_EQ(refusal(RenderOptions{}), ""); }

TEST(RenderOptions, EachOptionOutOfRangeIsNamedWithItsRange) {
    RenderOptions o;
    o.spp = 0;
    EXPECT_EQ(refusal(o), "spp: must be an integer from 1 to 1048576, got 0");
    o = {};
    o.max_depth = 1025;
    EXPECT_EQ(refusal(o), "max_depth: must be an integer from 1 to 1024, got 1025");
    o = {};
    o.aa_threshold = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(refusal(o), "aa_threshold: must be a number in [0, 1], got nan");
    o = {};
    o.threads = -1;
    EXPECT_EQ(refusal(o), "threads: must be an integer from 0 to 1024, got -1");
    o = {};
    o.cache.error = 5;
    EXPECT_EQ(refusal(o), "cache.error: must be a number in [0.01, 4], got 5");
    o = {};
    o.tile_size = -1;
    EXPECT_NE(refusal(o).find("tile_size"), std::string::npos);
}

TEST(RenderOptions, TheBoundsAreInside) {
    RenderOptions o;
    o.spp = 1;
    o.max_depth = 1024;
    o.aa_threshold = 1;
    o.cache.error = 0.01f;  // the scene file's 0.01 as a float: in range
    EXPECT_EQ(refusal(o), "");
}

// The scene file's max_depth counts segments, the kernels count vertices: 2 (direct light)
// is one vertex, and 1 (emitters alone) renders as 2 does.
TEST(RenderOptions, MaxDepthBecomesPathVertices) {
    EXPECT_EQ(path_vertices(1), 1);
    EXPECT_EQ(path_vertices(2), 1);
    EXPECT_EQ(path_vertices(3), 2);
    EXPECT_EQ(path_vertices(1024), 1023);
}

// Seeds below 2^32 key the streams as they are; higher bits change the key.
TEST(RenderOptions, StreamSeedKeepsSmallSeeds) {
    EXPECT_EQ(stream_seed(5), 5u);
    EXPECT_NE(stream_seed(5 + (uint64_t(1) << 32)), 5u);
}
