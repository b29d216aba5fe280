#include "render/accel/ray_recorder.h"

#include <atomic>
#include <algorithm>
#include <mutex>

namespace patina {

namespace {
std::atomic<bool> g_on{false};
std::mutex g_mutex;
RecordedRays g_rays;
size_t g_limit = 0;
}  // namespace

void start_ray_recording(size_t limit) {
    std::lock_guard<std::mutex> lock(g_mutex);
    g_rays = RecordedRays{};
    g_limit = limit;
    g_on.store(true, std::memory_order_release);
}

RecordedRays stop_ray_recording() {
    std::lock_guard<std::mutex> lock(g_mutex);
    g_on.store(false, std::memory_order_release);
    RecordedRays out = std::move(g_rays);
    g_rays = RecordedRays{};
    return out;
}

bool ray_recording_on() { return g_on.load(std::memory_order_relaxed); }

void record_rays(const RayBatch& rays, size_t begin, size_t end, bool any_hit) {
    std::lock_guard<std::mutex> lock(g_mutex);
    if (!g_on.load(std::memory_order_relaxed)) return;
    const size_t room = g_limit - std::min(g_limit, g_rays.tmax.size());
    if (end - begin > room) {
        g_rays.truncated = true;
        end = begin + room;
    }
    g_rays.origins.insert(g_rays.origins.end(), rays.origins + 3 * begin, rays.origins + 3 * end);
    g_rays.directions.insert(g_rays.directions.end(), rays.directions + 3 * begin, rays.directions + 3 * end);
    for (size_t i = begin; i < end; ++i) {
        g_rays.tmin.push_back(rays.tmin);
        g_rays.tmax.push_back(rays.tmax ? rays.tmax[i] : rays.tmax_all);
        g_rays.any_hit.push_back(any_hit ? 1 : 0);
    }
}

}  // namespace patina
