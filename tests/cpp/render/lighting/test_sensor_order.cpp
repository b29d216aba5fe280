// The sensors' Morton order (render/lighting/sensor_order.h): a permutation, and on a grid
// given row by row its first 16 sensors are a 4 x 4 tile, not a row.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "render/lighting/sensor_order.h"

using namespace patina;

TEST(SensorOrder, AGridGivenRowByRowGoesTileByTile) {
    std::vector<float> points;
    for (int row = 0; row < 16; ++row)
        for (int column = 0; column < 16; ++column) points.insert(points.end(), {0.5f * column, 0.8f, 0.5f * row});
    const std::vector<uint32_t> order = morton_order(points.data(), 256);
    std::vector<uint32_t> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (uint32_t i = 0; i < 256; ++i) ASSERT_EQ(sorted[i], i);
    for (int i = 0; i < 16; ++i) {
        EXPECT_LT(order[i] % 16, 4u) << i;  // column
        EXPECT_LT(order[i] / 16, 4u) << i;  // row
    }
}
