#include "render/cache/cache_regions.h"

#include <algorithm>
#include <limits>

namespace patina {

size_t cache_point_bytes(const CachePoint& a) {
    return sizeof(CachePoint) + sizeof(float) * (a.radiance.capacity() + a.dist.capacity() + a.hit_point.capacity() +
                                                 a.hit_normal.capacity() + a.outline.capacity()) +
           a.kind.capacity() + sizeof(Surfel) * a.surfels.capacity() +
           sizeof(Silhouette) * a.silhouettes.capacity() +
           sizeof(int32_t) * (a.layer_start.capacity() + a.silhouette_start.capacity());
}

// Reprojection reads the radiance, the texel kinds, the surfels and the silhouettes; the
// hits and their normals only made the surfels.
void drop_build_data(CachePoint& a) {
    std::vector<float>().swap(a.hit_point);
    std::vector<float>().swap(a.hit_normal);
}

CacheRegions::CacheRegions(int width, int height, size_t budget_bytes, int generations)
    : m_width(width),
      m_height(height),
      m_x((width + kCacheRegionPixels - 1) / kCacheRegionPixels),
      m_y((height + kCacheRegionPixels - 1) / kCacheRegionPixels),
      m_budget(budget_bytes),
      m_slots(static_cast<size_t>(m_x) * m_y * std::max(generations, 1)) {}

std::vector<int> CacheRegions::overlapping(int x0, int y0, int x1, int y1) const {
    std::vector<int> out;
    const int k = kCacheRegionPixels;
    for (int ry = std::max(0, y0 / k); ry <= std::min(m_y - 1, (y1 - 1) / k); ++ry)
        for (int rx = std::max(0, x0 / k); rx <= std::min(m_x - 1, (x1 - 1) / k); ++rx) out.push_back(ry * m_x + rx);
    return out;
}

void CacheRegions::expect(int region, int uses, int generation) {
    std::lock_guard<std::mutex> lock(m_lock);
    slot(region, generation).uses += uses;
}

std::shared_ptr<const CacheRegion> CacheRegions::acquire(int region, const Build& build, int generation) {
    for (;;) {
        int claimed = -1;
        {
            std::unique_lock<std::mutex> lock(m_lock);
            Slot& region_slot = slot(region, generation);
            if (region_slot.state == kBuilt) {
                region_slot.last_use = ++m_clock;
                return region_slot.points;
            }
            if (region_slot.state == kEmpty) {
                region_slot.state = kBuilding;
                claimed = region;
            } else if (m_bytes.load() < m_budget) {
                // another thread builds it: build the next region that items will want
                for (int k = 1; k < count() && claimed < 0; ++k) {
                    Slot& next_slot = slot((region + k) % count(), generation);
                    if (next_slot.state == kEmpty && next_slot.uses > 0) {
                        next_slot.state = kBuilding;
                        claimed = (region + k) % count();
                    }
                }
            }
            if (claimed < 0) {
                m_changed.wait(lock, [&] { return region_slot.state != kBuilding; });
                continue;
            }
        }
        std::shared_ptr<const CacheRegion> made = build_into(claimed, generation, build);
        if (claimed == region) return made;
    }
}

// Room for a region about to be built: the regions no item holds are dropped until the
// kept ones, the builds in flight and this one (reckoned as large as the largest built so
// far) fit the budget. Made before the build, not after it: a region can be a large part
// of the budget (R = 128 at --cache-block 1: 100 MB and more), and the kept regions and a
// finished build together would exceed it by that much.
size_t CacheRegions::reserve_for_build() {
    std::lock_guard<std::mutex> lock(m_lock);
    m_building += m_largest;
    evict_over_budget();
    return m_largest;
}

std::shared_ptr<const CacheRegion> CacheRegions::build_into(int region, int generation, const Build& build) {
    const size_t reserved = reserve_for_build();
    auto made = std::make_shared<CacheRegion>();
    const int k = kCacheRegionPixels;
    const int x0 = (region % m_x) * k, y0 = (region / m_x) * k;
    try {
        build(region, x0, y0, std::min(x0 + k, m_width), std::min(y0 + k, m_height), *made);
    } catch (...) {
        std::lock_guard<std::mutex> lock(m_lock);
        m_building -= reserved;
        slot(region, generation).state = kEmpty;
        m_changed.notify_all();
        throw;
    }
    made->bytes = 0;
    for (const CachePoint& a : made->points) made->bytes += cache_point_bytes(a);
    for (const RegionHemisphere& h : made->hemispheres) made->bytes += region_hemisphere_bytes(h);
    std::lock_guard<std::mutex> lock(m_lock);
    m_building -= reserved;
    m_largest = std::max(m_largest, made->bytes);
    Slot& region_slot = slot(region, generation);
    region_slot.points = std::move(made);
    region_slot.state = kBuilt;
    region_slot.last_use = ++m_clock;
    m_bytes += region_slot.points->bytes;
    ++m_builds;
    std::shared_ptr<const CacheRegion> held = region_slot.points;  // not evicted before its item has it
    evict_over_budget();
    m_changed.notify_all();
    return held;
}

void CacheRegions::release(int region, int generation) {
    std::lock_guard<std::mutex> lock(m_lock);
    Slot& region_slot = slot(region, generation);
    if (region_slot.uses <= 0) return;  // uses never announced (a distributed render's): kept, up to the budget
    if (--region_slot.uses > 0 || region_slot.state != kBuilt) return;
    m_bytes -= region_slot.points->bytes;
    region_slot.points.reset();  // the items holding it keep it until they are done
    region_slot.state = kEmpty;
}

// Drops the least recently used regions that no item holds until the rest and the builds in
// flight fit the budget;
// an item that wants one again builds it again, the same points.
void CacheRegions::evict_over_budget() {
    while (m_bytes.load() + m_building > m_budget) {
        Slot* oldest = nullptr;
        for (Slot& candidate : m_slots) {
            const bool unheld = candidate.state == kBuilt && candidate.points.use_count() == 1;
            if (unheld && (!oldest || candidate.last_use < oldest->last_use)) oldest = &candidate;
        }
        if (!oldest) return;
        m_bytes -= oldest->points->bytes;
        oldest->points.reset();
        oldest->state = kEmpty;
    }
}

}  // namespace patina
