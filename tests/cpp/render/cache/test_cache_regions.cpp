// The radiance cache's shared regions (render/cache/cache_regions.h): which regions a tile
// overlaps, each region built once however many threads want it, freed after its last
// announced use, and dropped (then built again, the same) over the memory budget.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

#include "render/cache/cache_regions.h"

using namespace patina;

namespace {

// a region's "points": one cache point whose radiance holds the region's number and bounds
CacheRegions::Build counting_build(std::atomic<int>& builds) {
    return [&builds](int region, int x0, int y0, int x1, int y1, CacheRegion& out) {
        ++builds;
        CachePoint a;
        a.radiance = {static_cast<float>(region), static_cast<float>(x0), static_cast<float>(y0),
                      static_cast<float>(x1), static_cast<float>(y1)};
        a.radiance.resize(1 << 16);  // 256 KiB: a budget of a few regions is easy to pass
        out.points.push_back(a);
    };
}

// the bytes of a region counting_build makes
size_t region_bytes() {
    CachePoint a;
    a.radiance.resize(1 << 16);
    return cache_point_bytes(a);
}

}  // namespace

TEST(CacheRegions, ATileOverlapsTheRegionsUnderItsPixels) {
    const int k = kCacheRegionPixels;
    const CacheRegions r(3 * k + 5, 2 * k, 1 << 20);  // 4 x 2 regions, the last column 5 pixels wide
    EXPECT_EQ(r.count(), 8);
    EXPECT_EQ(r.overlapping(0, 0, 16, 16), (std::vector<int>{0}));
    EXPECT_EQ(r.overlapping(k - 1, 0, k + 1, k + 1), (std::vector<int>{0, 1, 4, 5}));
    EXPECT_EQ(r.overlapping(3 * k, k, 3 * k + 5, 2 * k), (std::vector<int>{7}));
}

TEST(CacheRegions, ARegionIsBuiltOnceForEveryThreadThatWantsIt) {
    const int k = kCacheRegionPixels;
    CacheRegions regions(2 * k, k, 64 << 20);
    regions.expect(0, 3);
    regions.expect(1, 3);
    std::atomic<int> builds{0};
    const CacheRegions::Build build = counting_build(builds);
    std::vector<std::thread> threads;
    std::atomic<int> wrong{0};
    for (int t = 0; t < 6; ++t)
        threads.emplace_back([&, t] {
            const int want = t % 2;
            const auto got = regions.acquire(want, build);
            if (got->points.size() != 1 || got->points[0].radiance[0] != static_cast<float>(want) ||
                got->points[0].radiance[1] != static_cast<float>(want * k))
                ++wrong;
            regions.release(want);
        });
    for (auto& t : threads) t.join();
    EXPECT_EQ(wrong.load(), 0);
    EXPECT_EQ(builds.load(), 2);  // each once: a thread waiting for one builds the other meanwhile
    EXPECT_EQ(regions.bytes(), 0u);  // every announced use released: both freed
}

TEST(CacheRegions, OverTheBudgetTheLeastRecentlyUsedRegionIsDroppedAndBuiltAgain) {
    const int k = kCacheRegionPixels;
    const size_t one = region_bytes();
    CacheRegions regions(3 * k, k, 2 * one + one / 2);  // room for two regions
    for (int r = 0; r < 3; ++r) regions.expect(r, 10);
    std::atomic<int> builds{0};
    const CacheRegions::Build build = counting_build(builds);
    {
        const auto held = regions.acquire(0, build);  // held: never dropped while an item has it
        regions.acquire(1, build);
        regions.acquire(2, build);  // over the budget: 1 is the oldest not held
        EXPECT_LE(regions.bytes(), 2 * one + one / 2);
        EXPECT_EQ(builds.load(), 3);
        EXPECT_EQ(regions.acquire(0, build)->points[0].radiance[0], 0.0f);
        EXPECT_EQ(builds.load(), 3);  // 0 was kept
    }
    const auto again = regions.acquire(1, build);
    EXPECT_EQ(builds.load(), 4);  // built again...
    EXPECT_EQ(again->points[0].radiance[0], 1.0f);  // ...the same
    EXPECT_EQ(again->points[0].radiance[1], static_cast<float>(k));
}

TEST(CacheRegions, ABuildMakesRoomFirstSoTheKeptRegionsAndTheNewOneFitTheBudget) {
    const int k = kCacheRegionPixels;
    const size_t one = region_bytes();
    const size_t budget = 2 * one + one / 2;  // room for two regions
    CacheRegions regions(4 * k, k, budget);
    for (int r = 0; r < 4; ++r) regions.expect(r, 10);
    std::atomic<int> builds{0};
    const CacheRegions::Build counted = counting_build(builds);
    size_t most = 0;  // the kept regions' bytes while one is built, plus the one built
    const CacheRegions::Build build = [&](int region, int x0, int y0, int x1, int y1, CacheRegion& out) {
        counted(region, x0, y0, x1, y1, out);
        most = std::max(most, regions.bytes() + one);
    };
    const auto held = regions.acquire(0, build);
    for (int r = 1; r < 4; ++r) regions.acquire(r, build);
    EXPECT_EQ(builds.load(), 4);
    EXPECT_LE(most, budget);  // dropping after the build would have held three regions at once
    EXPECT_LE(regions.bytes(), budget);
}

// A region is kept once per generation: each generation's is built by that generation's
// build, freed after its own announced uses, and a thread waiting for one builds only
// regions of the same generation meanwhile (a later generation's would wait in memory).
TEST(CacheRegions, EachGenerationBuildsAndFreesItsOwnRegions) {
    const int k = kCacheRegionPixels;
    CacheRegions regions(2 * k, k, 64 << 20, 2);
    EXPECT_EQ(regions.count(), 2);  // regions of one generation
    for (int g = 0; g < 2; ++g)
        for (int r = 0; r < 2; ++r) regions.expect(r, 1, g);
    std::atomic<int> builds{0};
    const CacheRegions::Build counted = counting_build(builds);
    auto build_of = [&](int generation) -> CacheRegions::Build {
        return [&, generation](int region, int x0, int y0, int x1, int y1, CacheRegion& out) {
            counted(region, x0, y0, x1, y1, out);
            out.points[0].radiance[0] = static_cast<float>(10 * generation + region);
        };
    };
    const auto first = regions.acquire(1, build_of(0), 0);
    const auto second = regions.acquire(1, build_of(1), 1);
    EXPECT_EQ(builds.load(), 2);  // the same region, once per generation
    EXPECT_EQ(first->points[0].radiance[0], 1.0f);
    EXPECT_EQ(second->points[0].radiance[0], 11.0f);
    EXPECT_EQ(second->points[0].radiance[1], static_cast<float>(k));  // the same pixels
    const size_t both = regions.bytes();
    regions.release(1, 0);
    EXPECT_EQ(regions.bytes(), both / 2);  // generation 0's freed, generation 1's kept
    EXPECT_EQ(regions.acquire(1, build_of(1), 1)->points[0].radiance[0], 11.0f);
    EXPECT_EQ(builds.load(), 2);
}
