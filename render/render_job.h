// A render in the background: the image split into tiles, the samples of every pixel
// split into passes, (pass, tile) work items taken pass by pass by one worker per thread.
// Each tile's passes are added in order, so the image depends on the seed only (not on
// the thread count or timing); a cancelled render keeps every finished pass, and each
// pixel is the mean of the samples it got: a valid, noisier image. A cancel always lets
// the first pass finish, so no pixel of a cancelled image is left without a sample.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "render/antialiasing/adaptive_sampler.h"
#include "render/cache/cache_regions.h"
#include "render/camera/film.h"
#include "render/camera/pixel_sampler.h"
#include "render/guiding/guide_training.h"
#include "render/integrators/integrator.h"
#include "render/render_options.h"
#include "render/scene.h"

namespace patina {

struct RenderProgress {
    size_t items_done = 0, items_total = 0;
    size_t rays = 0;         // rays traced so far (camera, bounce and shadow)
    size_t samples_done = 0; // camera samples finished
    // the radiance cache: cache points built, first-hit points served, and of their
    // hemispheres' texels those reprojected (or known empty) and those traced
    size_t cache_points = 0, cache_queries = 0, cache_texels_reprojected = 0, cache_texels_traced = 0;
    double seconds = 0;
    bool finished = false, cancelled = false;
    bool preparing = false;  // the adaptive sampler's geometric pre-pass runs (no work item has begun)
};

class RenderJob {
public:
    RenderJob(const RenderScene& scene, const RenderOptions& options);  // checks the options (check_render_options)
    ~RenderJob();
    RenderJob(const RenderJob&) = delete;
    RenderJob& operator=(const RenderJob&) = delete;

    void start();   // returns at once; the workers run until done or cancelled
    // First call: the workers finish the first pass (every pixel gets a sample), then stop
    // at the items in flight. A second call: stop at the items in flight now (an abort:
    // pixels may have no sample, so don't keep the image). A worker's error aborts too.
    void cancel();
    void wait();    // joins the workers; rethrows a worker's exception
    RenderProgress progress() const;
    const Camera& camera() const { return m_scene.camera; }

    // The image, each pixel the mean of its samples (H x W x 3 etc.); samples: per pixel.
    // Call after wait() (a cancelled job: the passes that finished).
    void resolve(float* rgb, float* albedo, float* normal, float* depth, float* lux, float* samples) const;
    // The adaptive sampler's per-pixel level and rays (render/antialiasing/adaptive_sampler.h; empty for
    // the uniform sampler). Call after wait().
    const AaStats& aa_stats() const { return m_aa_stats; }
    // Time per integrator stage summed over the workers, and their time in work items
    // (render/integrators/stage_timer.h). Call after wait().
    StageTimes stage_times() const;

    // A distributed render (python/patina/batch/render_tiles.py): processes render chosen
    // tiles' passes on their own job of the same scene and settings and hand each tile's
    // sums on (read_tile); the next pass continues from them (write_tile), so each tile's
    // passes are still added in order and the image is the same bit for bit. Not with start().
    int tile_count() const { return static_cast<int>(m_tile_passes.size()); }
    int pass_count() const { return static_cast<int>(m_pass_begin.size()) - 1; }
    TileRect tile_rect(int tile) const;
    // Passes [first, end) of each of `tiles`, one after the other on the calling thread,
    // added to what the film holds for them (passes [0, first) by write_tile); other tiles
    // may render on other threads at once. A calling thread keeps its scratch buffers from
    // call to call, as a local worker keeps them from item to item.
    struct TileWork {
        size_t rays = 0, samples = 0;  // rays traced, camera samples taken
        // the radiance cache's counts (as progress() gives them for a started job)
        size_t cache_points = 0, cache_queries = 0, cache_texels_reprojected = 0, cache_texels_traced = 0;
    };
    TileWork render_tiles(const std::vector<int>& tiles, int first, int end);
    // The tile's sums (Film::kChannels doubles a pixel, row by row) and, for the adaptive
    // sampler, its pixels' aa_stats (nullptr for the uniform sampler).
    void read_tile(int tile, double* sums, uint8_t* aa_level, uint8_t* aa_rays) const;
    void write_tile(int tile, const double* sums, const uint8_t* aa_level, const uint8_t* aa_rays);

private:
    struct Item {
        int tile, pass;
    };
    struct Samplers;
    void worker();
    void prepare_adaptive(int threads);  // the first worker: the pre-pass, then the others go on
    void wait_for_hints();
    std::vector<int> tiles_costliest_first(const AaEdgeHints& hints) const;
    // returns the camera samples it took
    size_t run_item(const Item& item, PixelSampler& sampler, PathScratch& scratch,
                    std::vector<CameraSample>& camera_samples, std::vector<PathResult>& out);
    // the radiance cache's regions: announce the items of every pass of `tiles`; the
    // generation a pass's items take them from (render/cache/cache_generations.h); build one
    void expect_cache_regions(const std::vector<int>& tiles);
    int cache_generation(int pass) const { return pass / m_cache_generation_passes; }
    std::vector<int> cache_regions_near(int tile) const;
    void build_cache_region(int generation, int x0, int y0, int x1, int y1, CacheRegion& out,
                            PathScratch& scratch) const;

    const RenderScene& m_scene;
    RenderOptions m_settings;
    uint32_t m_seed;  // stream_seed of the options' seed
    IntegratorSettings m_integrator;
    const RenderKernels* m_kernels;
    int m_tiles_x = 0, m_tiles_y = 0;
    std::vector<int> m_pass_begin;  // sample index where each pass starts; back() = spp
    int m_cache_generation_passes = 1;  // passes whose items share one build of the cache's regions
    size_t m_item_count = 0;  // passes x tiles, taken pass by pass
    std::vector<std::atomic<int>> m_tile_passes;  // passes finished per tile
    Film m_film;
    AaStats m_aa_stats;
    // the radiance cache's points shared by the items (render/cache/cache_regions.h; null: no cache stage)
    std::unique_ptr<CacheRegions> m_cache_regions;
    // cache-guided's trained guide (render/guiding/guide_training.h; null: none), trained by
    // the workers before their first item
    std::unique_ptr<guiding::GuideTraining> m_guide_training;
    AaEdgeHints m_aa_hints;  // the adaptive sampler's geometric pre-pass, computed once
    std::vector<int> m_tile_order;  // the tiles in the order each pass's items take them (empty: the image's)
    std::mutex m_hints_lock;  // with m_hints_ready: the workers wait for start()'s pre-pass
    std::condition_variable m_hints_ready;
    std::once_flag m_aa_hints_once;  // render_tiles: computed by the first call, whichever thread
    std::atomic<size_t> m_next{0}, m_done{0}, m_rays{0}, m_samples_done{0};
    std::atomic<size_t> m_cache_points{0}, m_cache_queries{0}, m_cache_reprojected{0}, m_cache_traced{0};
    std::atomic<bool> m_preparing{false};  // start()'s adaptive pre-pass has not finished
    std::atomic<int> m_cancels{0};  // cancel() calls: 1 = after the first pass, 2 = now
    std::vector<std::thread> m_threads;
    mutable std::mutex m_error_lock;
    StageTimes m_stage_times;  // the finished workers' sums (under m_error_lock)
    std::exception_ptr m_error;
    std::chrono::steady_clock::time_point m_start;
    std::atomic<int64_t> m_last_done_ns{0};  // when the last item so far finished, since m_start
    bool m_started = false;
};

}  // namespace patina
