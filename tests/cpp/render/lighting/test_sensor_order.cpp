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

// The order is a stable sort by Morton code, whatever the sort: checked against std::sort of
// (code, index) pairs, the codes recomputed here by sensor_order.cpp's formula, on random
// points each given three times (equal codes, kept in their input order).
uint32_t morton_code(const float* p, const float* lo, const float* cells_per_unit) {
    uint32_t code = 0;
    for (int a = 0; a < 3; ++a) {
        const auto cell = static_cast<uint32_t>(std::min((p[a] - lo[a]) * cells_per_unit[a], 1023.0f));
        for (int bit = 0; bit < 10; ++bit) code |= ((cell >> bit) & 1u) << (3 * bit + a);
    }
    return code;
}

TEST(SensorOrder, IsAStableSortByMortonCode) {
    std::vector<float> points;
    uint32_t state = 12345u;
    const auto next = [&] { return float((state = state * 1664525u + 1013904223u) >> 8) * 0x1p-24f; };
    for (int i = 0; i < 3000; ++i) {
        const float p[3] = {40.0f * next() - 20.0f, 0.75f + next(), 30.0f * next() - 15.0f};
        for (int copy = 0; copy < 3; ++copy) points.insert(points.end(), p, p + 3);
    }
    const size_t n = points.size() / 3;
    float lo[3], hi[3], cells_per_unit[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = hi[a] = points[a];
        for (size_t i = 0; i < n; ++i) lo[a] = std::min(lo[a], points[3 * i + a]), hi[a] = std::max(hi[a], points[3 * i + a]);
        cells_per_unit[a] = 1023 / (hi[a] - lo[a]);
    }
    std::vector<std::pair<uint32_t, uint32_t>> keyed;
    for (uint32_t i = 0; i < n; ++i) keyed.emplace_back(morton_code(&points[3 * i], lo, cells_per_unit), i);
    std::sort(keyed.begin(), keyed.end());
    const std::vector<uint32_t> order = morton_order(points.data(), n);
    for (size_t i = 0; i < n; ++i) ASSERT_EQ(order[i], keyed[i].second) << i;
}
