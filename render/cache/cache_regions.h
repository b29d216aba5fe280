// The radiance cache's cache points shared by the work items of a render
// (docs/radiance-cache.md, "Regions"). The image is split into regions of
// kCacheRegionPixels x kCacheRegionPixels pixels; a region's cache points are placed and
// built by a pre-pass of its own (camera rays through its pixels' centres, keys from the
// seed and the pixel) that depends on nothing but the region, and then serve every pass of
// every tile that overlaps it. So a cache point is built once per region instead of once
// per (tile, pass), and the image still depends on the seed only: whichever thread builds
// a region, in whatever order, builds the same points -- and a region dropped from memory
// and built again is the same region, which is what bounds the memory: a region is freed
// when its last item is done, and regions no item holds are dropped (least recently used
// first) to keep the regions kept and the builds in flight within a budget -- room made
// before each build. The regions the items in flight hold are beyond any budget's reach:
// python/patina/render/cache_memory.py states them before a render.
//
// A render's passes fall into generations (render/cache/cache_generations.h): every
// generation builds each region again with numbers of its own, so the noise a region's
// cache points share averages out over the generations as a pixel's own noise does over its
// samples. A region is kept once per generation (slot generation x count() + region, 40
// bytes of bookkeeping each: 84 MB for a 4K image's 8160 regions at 4096 spp); the
// items take the generations in order, so one generation's regions are freed before most of
// the next one's are built.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "render/cache/cache_point.h"
#include "render/cache/region_hemisphere.h"

namespace patina {

constexpr int kCacheRegionPixels = 32;
constexpr size_t kCacheRegionBudgetBytes = size_t{256} << 20;

// One region's cache points (their build-only data dropped: cache_point_bytes) and, for
// `cache`, its pre-pass queries' reconstructed hemispheres.
struct CacheRegion {
    std::vector<CachePoint> points;
    std::vector<RegionHemisphere> hemispheres;
    size_t bytes = 0;
};

// The memory a cache point keeps, and its build-only arrays (hits and their normals) dropped.
size_t cache_point_bytes(const CachePoint& a);
void drop_build_data(CachePoint& a);

class CacheRegions {
public:
    // build(region, x0, y0, x1, y1, out): the region's cache points, for its pixels [x0, x1) x [y0, y1)
    using Build = std::function<void(int region, int x0, int y0, int x1, int y1, CacheRegion& out)>;

    CacheRegions(int width, int height, size_t budget_bytes = kCacheRegionBudgetBytes, int generations = 1);

    int count() const { return m_x * m_y; }  // regions of one generation
    // The regions that pixels [x0, x1) x [y0, y1) overlap, in order.
    std::vector<int> overlapping(int x0, int y0, int x1, int y1) const;
    // Announces `uses` more items that will acquire and release the region of the generation.
    void expect(int region, int uses, int generation = 0);
    // The region's points of the generation, built with `build` (which builds that generation's)
    // if they are not in memory. While another thread builds it, this one builds the
    // generation's next region nobody has built yet (work that later items need: no thread
    // idles while a neighbour builds what both need).
    std::shared_ptr<const CacheRegion> acquire(int region, const Build& build, int generation = 0);
    // One announced use done: the last one frees the region (one never announced: kept
    // until the budget drops it).
    void release(int region, int generation = 0);
    size_t bytes() const { return m_bytes.load(); }
    size_t builds() const { return m_builds.load(); }

private:
    enum State : int { kEmpty = 0, kBuilding = 1, kBuilt = 2 };
    struct Slot {
        std::atomic<int> state{kEmpty};
        std::shared_ptr<const CacheRegion> points;  // under m_lock
        int uses = 0;                               // announced uses left (under m_lock)
        uint64_t last_use = 0;                      // under m_lock
    };
    Slot& slot(int region, int generation) { return m_slots[static_cast<size_t>(generation) * count() + region]; }
    std::shared_ptr<const CacheRegion> build_into(int region, int generation, const Build& build);
    size_t reserve_for_build();  // what it reserved, given back when the build ends
    void evict_over_budget();  // under m_lock

    int m_width, m_height, m_x, m_y;
    size_t m_budget;
    std::vector<Slot> m_slots;
    mutable std::mutex m_lock;
    std::condition_variable m_changed;  // a region built, or its build failed
    std::atomic<size_t> m_bytes{0}, m_builds{0};
    uint64_t m_clock = 0;  // under m_lock
    size_t m_largest = 0;   // the largest region built so far (under m_lock)
    size_t m_building = 0;  // what the builds in flight were reckoned at (under m_lock)
};

}  // namespace patina
