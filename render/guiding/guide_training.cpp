#include "render/guiding/guide_training.h"

#include <algorithm>
#include <chrono>

#include "render/samplers/rng.h"

namespace patina::guiding {

namespace {
constexpr uint32_t kTrainingSalt = 0x6a09e667u;  // the training's streams: not any pixel's render samples
constexpr size_t kMaxBatch = 4096;               // camera samples traced as one wavefront (as the render job's)
}  // namespace

GuideTraining::GuideTraining(const RenderScene& scene, const IntegratorSettings& settings, const RenderKernels& kernels,
                             uint32_t seed)
    : m_scene(scene),
      m_settings(settings),
      m_kernels(kernels),
      m_seed(seed),
      m_width(scene.camera.width),
      m_passes(settings.cache.train_passes) {
    for (int y = 0; y < scene.camera.height; y += kTrainingTile)
        for (int x = 0; x < scene.camera.width; x += kTrainingTile)
            m_tiles.push_back({x, y, std::min(x + kTrainingTile, scene.camera.width),
                               std::min(y + kTrainingTile, scene.camera.height)});
    m_tile_records.resize(m_tiles.size());
    m_settings.indirect_illuminance = false;  // no sensor paths: the records are the camera paths'
    m_settings.mode = IntegratorMode::CacheGuided;
    m_settings.passes = 1;
    if (settings.cache.train_max_depth > 0) m_settings.max_depth = path_vertices(settings.cache.train_max_depth);
}

void GuideTraining::train_tile(int pass, int tile, PathScratch& scratch) {
    const TileRect& r = m_tiles[tile];
    const int spp = m_settings.cache.train_spp;
    const uint32_t seed = hash_u32(m_seed ^ kTrainingSalt ^ hash_u32(static_cast<uint32_t>(pass)));
    GuideRecordSink sink;
    std::vector<CameraSample> camera_samples;
    std::vector<PathResult> out;
    scratch.guide_sink = &sink;
    scratch.guide_field = pass > 0 ? &m_field : nullptr;
    auto flush = [&] {
        if (camera_samples.empty()) return;
        m_kernels.jitter_pixel_positions(m_settings.sampler, camera_samples.data(), camera_samples.size());
        out.resize(camera_samples.size());
        m_kernels.trace_paths(m_scene, m_settings, camera_samples.data(), camera_samples.size(), out.data(), scratch);
        camera_samples.clear();
    };
    for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) {
            const uint32_t key = stream_key(seed, static_cast<uint32_t>(y) * static_cast<uint32_t>(m_width) + x);
            for (int s = 0; s < spp; ++s)
                camera_samples.push_back({static_cast<float>(x), static_cast<float>(y), key, static_cast<uint32_t>(s)});
            if (camera_samples.size() + spp > kMaxBatch) flush();
        }
    flush();
    m_tile_records[tile] = std::move(sink.records);
}

void GuideTraining::take_part(PathScratch& scratch, const std::function<bool()>& stop) {
    const GuideField* field_before = scratch.guide_field;
    GuideRecordSink* sink_before = scratch.guide_sink;
    std::unique_lock<std::mutex> lock(m_lock);
    while (m_pass < m_passes) {
        if (stop()) break;
        if (m_next_tile >= m_tiles.size()) {  // the pass's last tiles are in other threads' hands
            m_pass_done.wait_for(lock, std::chrono::milliseconds(20));
            continue;
        }
        const int pass = m_pass, tile = static_cast<int>(m_next_tile++);
        lock.unlock();
        train_tile(pass, tile, scratch);
        lock.lock();
        if (++m_tiles_done < m_tiles.size()) continue;
        // the pass's last tile: its records join the others in tile order, the field is built again
        for (std::vector<GuideRecord>& t : m_tile_records) {
            m_records.insert(m_records.end(), t.begin(), t.end());
            std::vector<GuideRecord>().swap(t);
        }
        m_field.build(m_records);
        ++m_pass;
        m_next_tile = m_tiles_done = 0;
        m_pass_done.notify_all();
    }
    scratch.guide_field = field_before;
    scratch.guide_sink = sink_before;
}

}  // namespace patina::guiding
