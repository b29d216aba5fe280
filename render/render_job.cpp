#include "render/render_job.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/parallel.h"
#include "render/cache/cache_generations.h"
#include "render/samplers/rng.h"

namespace patina {
namespace {

constexpr size_t kMaxBatch = 4096;  // camera samples traced as one wavefront
constexpr uint32_t kCacheRegionSalt = 0x2c1b3c6du;  // the regions' pre-pass streams: not any pixel's samples

// f(k, i) for the tile's pixels row by row: k counts them, i is the pixel's index in the image.
template <class F>
void for_each_pixel(const TileRect& r, int width, F&& f) {
    size_t k = 0;
    for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) f(k++, static_cast<size_t>(y) * width + x);
}

}  // namespace

RenderJob::RenderJob(const RenderScene& scene, const RenderOptions& settings)
    : m_scene(scene),
      m_settings(settings),
      m_seed(stream_seed(settings.seed)),
      m_kernels(&render_kernels_for(settings.width)),
      m_film(std::max(scene.camera.width, 1), std::max(scene.camera.height, 1)) {
    check_render_options(settings);
    if (m_settings.tile_size == 0)
        m_settings.tile_size = settings.aa == RenderOptions::Aa::Adaptive ? kAdaptiveTileSize : kUniformTileSize;
    const Camera& c = scene.camera;
    if (c.width < 1 || c.height < 1) throw std::invalid_argument("the image must be at least 1 x 1 pixels");
    m_integrator.max_depth = path_vertices(settings.max_depth);
    m_integrator.indirect_illuminance = settings.indirect_illuminance;
    m_integrator.sampler = settings.sampler;
    m_integrator.mode = settings.mode;
    m_integrator.cache = settings.cache;
    // Where the adaptive sampler's positions are all its sample depends on (one delta light,
    // direct light only: aa_sample_is_signal), the paths' numbers change nothing in the image
    // (only the BRDF-sampled direction, whose ray can reach nothing that emits): independent
    // numbers give the same image bit for bit and cost a third of Owen-scrambled Sobol's
    // (docs/antialiasing.md, "Measured").
    if (settings.aa == RenderOptions::Aa::Adaptive && aa_sample_is_signal(scene, m_integrator))
        m_integrator.sampler = SamplerKind::Independent;
    m_tiles_x = (c.width + m_settings.tile_size - 1) / m_settings.tile_size;
    m_tiles_y = (c.height + m_settings.tile_size - 1) / m_settings.tile_size;
    // at least `passes` passes, each of at most max_pass_spp samples; the radiance cache's
    // integrators as few as that allows: each work item reconstructs the hemispheres of its own
    // queries, a cost a pass (the regions' cache points are built once a generation of 16 samples)
    const int min_passes = settings.mode == IntegratorMode::Path ? std::max(settings.passes, 1) : 1;
    // the adaptive sampler: one pattern a pass (its rounds are the levels)
    const int per_pass = settings.aa == RenderOptions::Aa::Adaptive
                             ? 1
                             : std::clamp((settings.spp + min_passes - 1) / min_passes, 1, settings.max_pass_spp);
    const int passes = (settings.spp + per_pass - 1) / per_pass;
    m_integrator.passes = passes;
    for (int p = 0; p <= passes; ++p)
        m_pass_begin.push_back(static_cast<int>(static_cast<int64_t>(settings.spp) * p / passes));
    const int tiles = m_tiles_x * m_tiles_y;
    m_item_count = static_cast<size_t>(passes) * tiles;  // item k: pass k / tiles, tile k % tiles
    m_tile_passes = std::vector<std::atomic<int>>(tiles);
    for (auto& a : m_tile_passes) a.store(0);
    // the radiance cache's shared points (cache_regions.h), where the cache stage runs
    // (cache-guided with a trained guide: the guide's training, and no cache points); `cache`
    // builds them again every generation (cache_generations.h), cache-guided's only guide
    // unbiased paths and serve every pass
    const bool trained_guide = settings.mode == IntegratorMode::CacheGuided && settings.cache.train_passes > 0;
    m_cache_generation_passes = settings.mode == IntegratorMode::Cache ? cache_passes_per_generation(per_pass) : passes;
    const int generations = (passes + m_cache_generation_passes - 1) / m_cache_generation_passes;
    if (settings.mode != IntegratorMode::Path && m_integrator.max_depth > 1 && !trained_guide)
        m_cache_regions = std::make_unique<CacheRegions>(c.width, c.height, kCacheRegionBudgetBytes, generations);
    const int train_depth = path_vertices(settings.cache.train_max_depth > 0 ? settings.cache.train_max_depth : settings.max_depth);
    if (trained_guide && train_depth > 1)
        m_guide_training = std::make_unique<guiding::GuideTraining>(scene, m_integrator, *m_kernels, m_seed);
    if (settings.aa == RenderOptions::Aa::Adaptive) {
        m_aa_stats.level.assign(static_cast<size_t>(c.width) * c.height, 0);
        m_aa_stats.rays.assign(static_cast<size_t>(c.width) * c.height, 0);
        m_aa_stats.pattern.assign(static_cast<size_t>(c.width) * c.height, 0);
    }
}

RenderJob::~RenderJob() {
    m_cancels.store(2);
    for (auto& t : m_threads)
        if (t.joinable()) t.join();
}

void RenderJob::start() {
    if (m_started) throw std::logic_error("a render job starts once");
    m_started = true;
    m_start = std::chrono::steady_clock::now();
    const int threads = m_settings.threads > 0 ? m_settings.threads : default_thread_count();
    std::vector<int> all(m_tile_passes.size());
    for (size_t t = 0; t < all.size(); ++t) all[t] = static_cast<int>(t);
    expect_cache_regions(all);
    if (m_settings.aa != RenderOptions::Aa::Adaptive) {
        for (int i = 0; i < threads; ++i) m_threads.emplace_back([this] { worker(); });
        return;
    }
    // the adaptive sampler's geometric pre-pass (part of the render's time) on the first
    // worker, the others waiting for it: start() returns at once and progress() says the
    // pre-pass runs (the preview ball's takes 15-18 ms of CPU; it grows with the mesh's edges).
    // The workers are started once: a thread of its own that started them after the pre-pass
    // put a thread's start in the render's serial part.
    m_preparing.store(true);
    for (int i = 0; i < threads; ++i)
        m_threads.emplace_back([this, threads, i] {
            if (i == 0) prepare_adaptive(threads);
            wait_for_hints();
            worker();
        });
}

// The pre-pass's hints and the tiles' order from them; then the waiting workers go on.
void RenderJob::prepare_adaptive(int threads) {
    try {
        m_aa_hints = project_feature_edges(m_scene, m_settings.aa_threshold, threads);
        m_tile_order = tiles_costliest_first(m_aa_hints);
    } catch (...) {
        std::lock_guard<std::mutex> lock(m_error_lock);
        if (!m_error) m_error = std::current_exception();
        m_cancels.store(2);
    }
    {
        std::lock_guard<std::mutex> lock(m_hints_lock);
        m_preparing.store(false);
    }
    m_hints_ready.notify_all();
}

void RenderJob::wait_for_hints() {
    std::unique_lock<std::mutex> lock(m_hints_lock);
    m_hints_ready.wait(lock, [this] { return !m_preparing.load(); });
}

// The tiles by the pixels their hints flag, most first (ties in the image's order): the tiles
// where edges are dense cost most (pixels of 13-25 rays on the checkerboard's horizon), and
// taken last they leave one thread finishing them while the other has none left. Counted on
// zones[0] alone: an edge in a pixel always flags a zone of it (edge_hints.cpp), and this
// count is in the render's serial part.
std::vector<int> RenderJob::tiles_costliest_first(const AaEdgeHints& hints) const {
    std::vector<int> flagged(m_tile_passes.size(), 0);
    if (!hints.empty())
        for (int tile = 0; tile < tile_count(); ++tile)
            for_each_pixel(tile_rect(tile), hints.width,
                           [&](size_t, size_t i) { flagged[tile] += hints.zones[0][i] != 0; });
    std::vector<int> order(flagged.size());
    for (size_t t = 0; t < order.size(); ++t) order[t] = static_cast<int>(t);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return flagged[a] > flagged[b]; });
    return order;
}

void RenderJob::cancel() { m_cancels.fetch_add(1); }

void RenderJob::wait() {
    for (auto& t : m_threads)
        if (t.joinable()) t.join();
    std::lock_guard<std::mutex> lock(m_error_lock);
    if (m_error) std::rethrow_exception(m_error);
}

RenderProgress RenderJob::progress() const {
    RenderProgress p;
    p.items_done = m_done.load();
    p.items_total = m_item_count;
    p.rays = m_rays.load();
    p.samples_done = m_samples_done.load();
    p.cache_points = m_cache_points.load();
    p.cache_queries = m_cache_queries.load();
    p.cache_texels_reprojected = m_cache_reprojected.load();
    p.cache_texels_traced = m_cache_traced.load();
    p.cancelled = m_cancels.load() > 0;
    p.preparing = m_preparing.load();
    p.finished = p.items_done == p.items_total;
    // a finished job's time is when its last item finished, not when someone asked
    const double now = m_started ? std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count() : 0;
    p.seconds = p.finished ? 1e-9 * static_cast<double>(m_last_done_ns.load()) : now;
    return p;
}

// One thread's pixel samplers, the settings' one in use.
struct RenderJob::Samplers {
    UniformSampler uniform;
    AdaptiveSampler adaptive;
    PixelSampler& active;
    explicit Samplers(RenderJob& j)
        : uniform(j.m_film, *j.m_kernels, j.m_seed, j.m_settings.sampler, j.m_pass_begin, kMaxBatch),
          adaptive(j.m_film, j.m_scene, *j.m_kernels, j.m_integrator, j.m_seed, j.m_settings.aa_threshold,
                   j.m_aa_stats, &j.m_aa_hints),
          active(j.m_settings.aa == RenderOptions::Aa::Adaptive ? static_cast<PixelSampler&>(adaptive)
                                                                 : static_cast<PixelSampler&>(uniform)) {}
};

void RenderJob::worker() {
    PathScratch scratch;
    // however the worker ends, its stage times join the job's
    struct AddStageTimes {
        RenderJob& job;
        const PathScratch& scratch;
        ~AddStageTimes() {
            std::lock_guard<std::mutex> lock(job.m_error_lock);
            job.m_stage_times += scratch.timer.times;
        }
    } add_stage_times{*this, scratch};
    scratch.timer.use_cpu_time(m_settings.stage_cpu_time);
    Samplers samplers(*this);
    PixelSampler& sampler = samplers.active;
    std::vector<CameraSample> camera_samples;
    std::vector<PathResult> out;
    try {
        if (m_guide_training) {  // the guide first, with every worker (part of the render's time)
            m_guide_training->take_part(scratch, [this] { return m_cancels.load() >= 2; });
            scratch.guide_field = &m_guide_training->field();
        }
        const size_t tiles = m_tile_passes.size();
        while (m_cancels.load() < 2) {
            const size_t k = m_next.fetch_add(1);
            if (k >= m_item_count) break;
            if (k >= tiles && m_cancels.load() > 0) break;  // cancelled: items k < tiles are the first pass
            const size_t place = k % tiles;  // the tile's place in this pass's order
            const Item item{m_tile_order.empty() ? static_cast<int>(place) : m_tile_order[place],
                            static_cast<int>(k / tiles)};
            // a tile's passes are added in order: wait for the previous one (rare: only when
            // there are fewer tiles than threads)
            while (m_tile_passes[item.tile].load(std::memory_order_acquire) != item.pass) {
                if (m_cancels.load() > 0) return;  // a later pass (item.pass > 0): not needed
                std::this_thread::yield();
            }
            const size_t before = scratch.rays_traced + sampler.rays_traced();
            const int64_t item_start = scratch.timer.now();
            const size_t points = scratch.cache_points, queries = scratch.cache_queries,
                         reprojected = scratch.cache_texels_reprojected, traced = scratch.cache_texels_traced;
            run_item(item, sampler, scratch, camera_samples, out);
            scratch.timer.times.item_ns += scratch.timer.now() - item_start;
            m_rays.fetch_add(scratch.rays_traced + sampler.rays_traced() - before);
            m_cache_points.fetch_add(scratch.cache_points - points);
            m_cache_queries.fetch_add(scratch.cache_queries - queries);
            m_cache_reprojected.fetch_add(scratch.cache_texels_reprojected - reprojected);
            m_cache_traced.fetch_add(scratch.cache_texels_traced - traced);
            m_tile_passes[item.tile].store(item.pass + 1, std::memory_order_release);
            const int64_t ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                                   std::chrono::steady_clock::now() - m_start).count();
            int64_t seen = m_last_done_ns.load();
            while (ns > seen && !m_last_done_ns.compare_exchange_weak(seen, ns)) {
            }
            m_done.fetch_add(1);
        }
    } catch (...) {
        std::lock_guard<std::mutex> lock(m_error_lock);
        if (!m_error) m_error = std::current_exception();
        m_cancels.store(2);
    }
}

StageTimes RenderJob::stage_times() const {
    std::lock_guard<std::mutex> lock(m_error_lock);
    return m_stage_times;
}

TileRect RenderJob::tile_rect(int tile) const {
    if (tile < 0 || tile >= tile_count()) throw std::out_of_range("tile " + std::to_string(tile) + " is not in the image");
    const Camera& cam = m_scene.camera;
    const int ts = m_settings.tile_size;
    const int x0 = (tile % m_tiles_x) * ts, y0 = (tile / m_tiles_x) * ts;
    return TileRect{x0, y0, std::min(x0 + ts, cam.width), std::min(y0 + ts, cam.height)};
}

// The regions whose hemispheres the tile's pixels may take: those under the tile and within
// a block of it (for `cache`, a pixel draws its hemisphere from the window of 2 x 2 blocks
// around it, across region edges too: cache_stages_impl.h, jittered_pixel). Only the
// regions under the tile itself serve its own queries' cache points.
std::vector<int> RenderJob::cache_regions_near(int tile) const {
    const TileRect r = tile_rect(tile);
    const int margin = m_integrator.mode == IntegratorMode::Cache ? m_integrator.cache.block : 0;
    const Camera& cam = m_scene.camera;
    return m_cache_regions->overlapping(std::max(r.x0 - margin, 0), std::max(r.y0 - margin, 0),
                                        std::min(r.x1 + margin, cam.width), std::min(r.y1 + margin, cam.height));
}

// Each region's uses in a generation: the tiles near it times the generation's passes,
// announced once a region and generation (a call a tile and pass would take the lock some
// 30 million times for a 4K image at 4096 spp).
void RenderJob::expect_cache_regions(const std::vector<int>& tiles) {
    if (!m_cache_regions) return;
    std::vector<int> tiles_near(m_cache_regions->count(), 0);
    for (const int tile : tiles)
        for (const int region : cache_regions_near(tile)) ++tiles_near[region];
    std::vector<int> passes_in(cache_generation(pass_count() - 1) + 1, 0);
    for (int pass = 0; pass < pass_count(); ++pass) ++passes_in[cache_generation(pass)];
    for (int region = 0; region < m_cache_regions->count(); ++region)
        if (tiles_near[region] > 0)
            for (size_t g = 0; g < passes_in.size(); ++g)
                m_cache_regions->expect(region, tiles_near[region] * passes_in[g], static_cast<int>(g));
}

// A region's cache points from its pre-pass: a camera ray through every pixel (generation 0's
// through its centre: cache_prepass_offset), its stream keyed by the generation's seed and
// the pixel (salted), traced on the calling thread's scratch.
void RenderJob::build_cache_region(int generation, int x0, int y0, int x1, int y1, CacheRegion& out,
                                   PathScratch& scratch) const {
    std::vector<CameraSample> prepass;
    const uint32_t seed = cache_generation_seed(m_seed ^ kCacheRegionSalt, generation);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const uint32_t pixel = static_cast<uint32_t>(y) * static_cast<uint32_t>(m_scene.camera.width) + x;
            const uint32_t key = stream_key(seed, pixel);
            prepass.push_back({static_cast<float>(x) + cache_prepass_offset(generation, key, 0),
                               static_cast<float>(y) + cache_prepass_offset(generation, key, 1), key, 0});
        }
    m_kernels->build_cache_region(m_scene, m_integrator, prepass.data(), prepass.size(), out.points, out.hemispheres,
                                  scratch);
}

size_t RenderJob::run_item(const Item& item, PixelSampler& sampler, PathScratch& scratch,
                           std::vector<CameraSample>& camera_samples, std::vector<PathResult>& out) {
    const TileRect rect = tile_rect(item.tile);
    // the cache points of the regions the tile overlaps, built if no one has, held for the item
    struct HeldRegions {
        CacheRegions* regions;
        std::vector<int> ids;
        std::vector<std::shared_ptr<const CacheRegion>> held;
        PathScratch& scratch;
        ~HeldRegions() {
            scratch.cache_shared.clear();
            scratch.cache_shared_hemispheres.clear();
            held.clear();
            for (const int r : ids) regions->release(r, generation);
        }
        int generation;
    } hold{m_cache_regions.get(), {}, {}, scratch, cache_generation(item.pass)};
    scratch.cache_shared.clear();
    scratch.cache_shared_hemispheres.clear();
    if (m_cache_regions) {
        const std::vector<int> under = m_cache_regions->overlapping(rect.x0, rect.y0, rect.x1, rect.y1);
        const CacheRegions::Build build = [&](int, int x0, int y0, int x1, int y1, CacheRegion& made) {
            build_cache_region(hold.generation, x0, y0, x1, y1, made, scratch);
        };
        for (const int r : cache_regions_near(item.tile)) {
            hold.held.push_back(m_cache_regions->acquire(r, build, hold.generation));
            hold.ids.push_back(r);
            if (std::find(under.begin(), under.end(), r) != under.end())
                for (const CachePoint& a : hold.held.back()->points) scratch.cache_shared.push_back(&a);
            for (const RegionHemisphere& h : hold.held.back()->hemispheres)
                scratch.cache_shared_hemispheres.push_back(&h);
        }
    }
    sampler.begin(rect, item.pass);
    size_t samples = 0;
    while (sampler.next_batch(camera_samples)) {
        out.resize(camera_samples.size());
        m_kernels->trace_paths(m_scene, m_integrator, camera_samples.data(), camera_samples.size(), out.data(),
                               scratch);
        sampler.take_results(camera_samples.data(), out.data(), camera_samples.size());
        m_samples_done.fetch_add(camera_samples.size());
        samples += camera_samples.size();
    }
    return samples;
}

RenderJob::TileWork RenderJob::render_tiles(const std::vector<int>& tiles, int first, int end) {
    if (m_started) throw std::logic_error("render_tiles is for a job that is not started");
    for (const int tile : tiles) tile_rect(tile);  // checks the tiles
    if (first < 0 || first > end || end > pass_count())
        throw std::out_of_range("passes [" + std::to_string(first) + ", " + std::to_string(end) + ") are not in [0, " +
                                std::to_string(pass_count()) + ")");
    // the adaptive sampler's geometric pre-pass, as start() makes it (on the settings'
    // threads too: the hints are the same for any count), the same for every tile
    std::call_once(m_aa_hints_once, [this] {
        const int threads = m_settings.threads > 0 ? m_settings.threads : default_thread_count();
        if (m_settings.aa == RenderOptions::Aa::Adaptive)
            m_aa_hints = project_feature_edges(m_scene, m_settings.aa_threshold, threads);
    });
    // The calling thread's buffers, kept from call to call as a local worker keeps them from
    // item to item: made anew each call, their megabytes are page-faulted in again each time
    // (a Dask worker's allocator returns freed memory to the system at once).
    thread_local PathScratch scratch;
    thread_local std::vector<CameraSample> camera_samples;
    thread_local std::vector<PathResult> out;
    Samplers samplers(*this);
    // the trained guide, by the first call (each process trains the same one for itself)
    scratch.guide_field = nullptr;
    if (m_guide_training) {
        m_guide_training->take_part(scratch);
        scratch.guide_field = &m_guide_training->field();
    }
    // (the cache's regions are not announced: later calls may want them; the budget bounds them)
    const size_t rays = scratch.rays_traced, points = scratch.cache_points, queries = scratch.cache_queries,
                 reprojected = scratch.cache_texels_reprojected, traced = scratch.cache_texels_traced;
    TileWork work;
    for (const int tile : tiles)
        for (int pass = first; pass < end; ++pass)
            work.samples += run_item(Item{tile, pass}, samplers.active, scratch, camera_samples, out);
    work.rays = scratch.rays_traced - rays + samplers.active.rays_traced();
    work.cache_points = scratch.cache_points - points;
    work.cache_queries = scratch.cache_queries - queries;
    work.cache_texels_reprojected = scratch.cache_texels_reprojected - reprojected;
    work.cache_texels_traced = scratch.cache_texels_traced - traced;
    return work;
}

void RenderJob::read_tile(int tile, double* sums, uint8_t* aa_level, uint8_t* aa_rays) const {
    const TileRect r = tile_rect(tile);
    m_film.read(r.x0, r.y0, r.x1, r.y1, sums);
    if (m_aa_stats.level.empty()) return;
    for_each_pixel(r, m_film.width(), [&](size_t k, size_t i) {
        aa_level[k] = m_aa_stats.level[i];
        aa_rays[k] = m_aa_stats.rays[i];
    });
}

void RenderJob::write_tile(int tile, const double* sums, const uint8_t* aa_level, const uint8_t* aa_rays) {
    if (m_started) throw std::logic_error("write_tile is for a job that is not started");
    const TileRect r = tile_rect(tile);
    m_film.write(r.x0, r.y0, r.x1, r.y1, sums);
    if (m_aa_stats.level.empty()) return;
    for_each_pixel(r, m_film.width(), [&](size_t k, size_t i) {
        m_aa_stats.level[i] = aa_level[k];
        m_aa_stats.rays[i] = aa_rays[k];
    });
}

void RenderJob::resolve(float* rgb, float* albedo, float* normal, float* depth, float* lux, float* samples) const {
    m_film.resolve(rgb, albedo, normal, depth, lux, samples);
}

}  // namespace patina
