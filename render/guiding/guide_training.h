// cache-guided's training (docs/radiance-cache.md, "The trained guide"): before the render's
// passes, a few short passes of the guided path tracer over the whole image, each pass's
// vertices recording the incident radiance they measured (guide_recording_impl.h), after
// which the guide (guide_field.h) is built again from the records of every pass so far; the
// render then samples the last one, read-only. The training's own samples are not added to
// the image: the guide is then a function of the scene, the settings and the seed alone, so
// a distributed render's processes (each training for itself) and a local one sample the
// same guide, and the image is the same bit for bit.
//
// Deterministic for any thread count: the threads taking part take a pass's tiles one by
// one, each tile's records go to the tile's own list (no shared mutable structure during a
// pass), and the last tile done merges the lists in tile order and builds the next field
// while the others wait for it.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

#include "render/camera/pixel_sampler.h"
#include "render/guiding/guide_field.h"
#include "render/guiding/guide_record.h"
#include "render/integrators/integrator.h"
#include "render/scene.h"

namespace patina::guiding {

class GuideTraining {
public:
    // settings.cache.train_passes passes of settings.cache.train_spp samples a pixel over the
    // scene camera's image, in tiles of kTrainingTile x kTrainingTile pixels (larger than the
    // render's: a wavefront of 4096 paths at 1 spp), the paths' streams keyed by `seed`
    // (salted: no pixel's render samples).
    static constexpr int kTrainingTile = 64;
    GuideTraining(const RenderScene& scene, const IntegratorSettings& settings, const RenderKernels& kernels,
                  uint32_t seed);
    // Trains on the calling thread, with any others that call at once, until the last pass's
    // field is built; returns early when stop() says so (between tiles). Leaves scratch's
    // guide pointers as it found them.
    void take_part(PathScratch& scratch, const std::function<bool()>& stop = [] { return false; });
    bool trained() const { return m_pass >= m_passes; }
    // The trained field (call after take_part returned without an abort).
    const GuideField& field() const { return m_field; }
    size_t records() const { return m_records.size(); }

private:
    void train_tile(int pass, int tile, PathScratch& scratch);
    const RenderScene& m_scene;
    IntegratorSettings m_settings;
    const RenderKernels& m_kernels;
    uint32_t m_seed;
    std::vector<TileRect> m_tiles;
    int m_width;
    int m_passes;
    std::mutex m_lock;
    std::condition_variable m_pass_done;
    int m_pass = 0;                 // the pass being trained (m_passes: done)
    size_t m_next_tile = 0, m_tiles_done = 0;
    std::vector<std::vector<GuideRecord>> m_tile_records;  // the pass's, per tile
    std::vector<GuideRecord> m_records;                    // every finished pass's, in tile order
    GuideField m_field;  // built from m_records after each pass; read by the next pass's tiles
};

}  // namespace patina::guiding
