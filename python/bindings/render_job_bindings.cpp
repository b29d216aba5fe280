// patina._core.RenderOptions, RenderJob and the job's typed results (RenderProgress,
// ResolvedImages, TileWork, StageSeconds). Every field is documented here, once; Python
// builds the options from the scene file (python/patina/render/run.py's job_settings).
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/unique_ptr.h>
#include <nanobind/stl/vector.h>

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "record.h"
#include "render/render_job.h"
#include "render/render_options.h"

namespace nb = nanobind;

namespace patina_py {
namespace {

// An enum's Python names, in the enum's order; an unknown name is the one-line error
// "<field>: 'x' is not one of 'a', 'b'".
template <class E, size_t N>
struct Names {
    const char* field;
    const char* names[N];

    std::string of(E value) const { return names[static_cast<size_t>(value)]; }
    E from(const std::string& name) const {
        std::string known;
        for (size_t i = 0; i < N; ++i) {
            if (name == names[i]) return static_cast<E>(i);
            known += (i ? ", '" : "'") + std::string(names[i]) + "'";
        }
        throw std::invalid_argument(std::string(field) + ": '" + name + "' is not one of " + known);
    }
};

using Options = patina::RenderOptions;
constexpr Names<Options::Aa, 2> kAaNames{"aa", {"uniform", "adaptive"}};
constexpr Names<patina::SamplerKind, 2> kSamplerNames{"sampler", {"sobol", "independent"}};
constexpr Names<patina::IntegratorMode, 3> kIntegratorNames{"integrator", {"path", "cache", "cache-guided"}};
constexpr Names<bool, 2> kClockNames{"stage_clock", {"wall", "cpu"}};

// A table of ranges as Python reads it: (key, integer, lo, hi), inclusive.
template <class Settings, size_t N>
nb::list ranges_of(const patina::SettingRange<Settings> (&table)[N]) {
    nb::list out;
    for (const auto& r : table) out.append(nb::make_tuple(r.key, r.integer, r.lo, r.hi));
    return out;
}

void bind_options(nb::module_& m) {
    using C = patina::CacheSettings;
    Record<C>(m, "CacheSettings", "The radiance cache's settings (docs/radiance-cache.md; render.cache in a scene file).")
        .field("resolution", &C::resolution, "texels per side of a cache point's hemisphere (R x R, equal solid angle)")
        .field("error", &C::error, "the reuse criterion's bound (larger: fewer cache points, more reuse): B uses A when |B - A| / R_A + sqrt(1 - nA.nB) <= error")
        .field("guide", &C::guide, "cache-guided: the probability of drawing a bounce from the cache points")
        .field("guide_bounces", &C::guide_bounces, "cache-guided: the bounces of a path the cache points draw (1: the first hit's)")
        .field("block", &C::block, "pixels per side of the blocks whose close points share one reconstruction")
        .field("hit_paths", &C::hit_paths, "cache: paths from a cache point's texel hit on a glossy surface")
        .field("light_samples", &C::light_samples, "cache: the light samples a camera sample takes at its first hit")
        .field("train_passes", &C::train_passes, "cache-guided: training passes of the trained guide (0: cache points guide)")
        .field("train_spp", &C::train_spp, "cache-guided: samples a pixel in each training pass")
        .field("train_guide", &C::train_guide, "cache-guided: the probability of drawing a bounce from the trained guide")
        .field("train_bounces", &C::train_bounces, "cache-guided: the bounces of a path the trained guide draws (1: the first hit's)")
        .field("train_max_depth", &C::train_max_depth,
               "the training paths' max_depth in segments (0: the render's); a measuring knob, no scene key")
        .finish();
    Record<Options>(m, "RenderOptions", "What a RenderJob renders: the scene file's render settings and how to run them.")
        .field("spp", &Options::spp, "samples a pixel (the adaptive sampler: patterns a pixel)")
        .field("max_depth", &Options::max_depth,
               "longest path in segments, the scene file's (Mitsuba 3's) convention: 2 = direct light, 3 = one bounce")
        .field("seed", &Options::seed, "the random seed, 0 to 2^63 - 1")
        .field("threads", &Options::threads, "worker threads (0: all hardware threads)")
        .field("width", &Options::width, "SIMD width 1, 4, 8 or 16 (0: the widest the CPU runs)")
        .field("tile_size", &Options::tile_size, "pixels per side of a tile (0: the sampler's own)")
        .field("passes", &Options::passes, "a pixel's samples are split into at least this many passes...")
        .field("max_pass_spp", &Options::max_pass_spp, "...of at most this many samples (a cancel waits for a pass)")
        .named(
            "aa", [](const Options& o) { return kAaNames.of(o.aa); },
            [](Options& o, const std::string& v) { o.aa = kAaNames.from(v); },
            "the pixel sampler: 'uniform' or 'adaptive' (docs/antialiasing.md)")
        .field("aa_threshold", &Options::aa_threshold, "the adaptive sampler's contrast threshold, in [0, 1]")
        .field("indirect_illuminance", &Options::indirect_illuminance,
               "the illuminance image counts the light the scene reflects, not only direct light")
        .named(
            "sampler", [](const Options& o) { return kSamplerNames.of(o.sampler); },
            [](Options& o, const std::string& v) { o.sampler = kSamplerNames.from(v); },
            "the paths' numbers: 'sobol' (Owen-scrambled) or 'independent' (docs/render.md)")
        .named(
            "stage_clock", [](const Options& o) { return kClockNames.of(o.stage_cpu_time); },
            [](Options& o, const std::string& v) { o.stage_cpu_time = kClockNames.from(v); },
            "stage_times() on 'wall' time or each thread's 'cpu' time")
        .named(
            "integrator", [](const Options& o) { return kIntegratorNames.of(o.mode); },
            [](Options& o, const std::string& v) { o.mode = kIntegratorNames.from(v); },
            "'path', 'cache' or 'cache-guided' (the scene's 'direct' is 'path' at max_depth 2)")
        .field("cache", &Options::cache, "the radiance cache's settings")
        .finish()
        .def("check", &patina::check_render_options,
             "ValueError naming the first option out of its range (as RenderJob checks them)");
    m.def(
        "render_option_ranges", [] { return ranges_of(patina::kRenderOptionRanges); },
        "The render options' ranges as (key, integer, lo, hi), inclusive: the one table (render/render_options.h) "
        "the scene reader's and the command line's checks read.");
    m.def(
        "cache_setting_ranges", [] { return ranges_of(patina::kCacheSettingRanges); },
        "The radiance cache's scene settings as (key, integer, lo, hi), inclusive: the one table "
        "(render/cache/cache_settings.h) the scene reader's and the command line's checks read.");
    // the cache's regions (render/cache/cache_regions.h): what patina.render.cache_memory estimates from
    m.attr("cache_region_pixels") = patina::kCacheRegionPixels;
    m.attr("cache_region_budget_bytes") = patina::kCacheRegionBudgetBytes;
    // the job's tiles by pixel sampler (render_job.cpp): which regions an item holds
    m.attr("tile_pixels") = nb::dict();
    m.attr("tile_pixels")["uniform"] = patina::kUniformTileSize;
    m.attr("tile_pixels")["adaptive"] = patina::kAdaptiveTileSize;
}

struct JobHandle {
    nb::object scene_ref;
    std::unique_ptr<patina::RenderJob> job;
};

std::unique_ptr<JobHandle> make_job(nb::object scene_obj, const Options& options) {
    SceneHandle& h = nb::cast<SceneHandle&>(scene_obj);
    prepare_for_render(h);
    auto j = std::make_unique<JobHandle>();
    j->scene_ref = scene_obj;
    j->job = std::make_unique<patina::RenderJob>(h.scene, options);
    return j;
}

// Seconds per integrator stage summed over the workers, their seconds in work items, and
// the rays and shading points counted (RenderJob::stage_times).
struct StageSeconds {
    nb::dict stages;
    double item_seconds = 0;
    uint64_t camera_rays = 0, secondary_rays = 0, shadow_rays = 0, shading_points = 0;
};

StageSeconds stage_times(const JobHandle& j) {
    const patina::StageTimes t = j.job->stage_times();
    StageSeconds out;
    for (int k = 0; k < patina::kStageCount; ++k)
        out.stages[patina::stage_name(static_cast<patina::Stage>(k))] = 1e-9 * static_cast<double>(t.ns[k]);
    out.item_seconds = 1e-9 * static_cast<double>(t.item_ns);
    out.camera_rays = t.camera_rays;
    out.secondary_rays = t.secondary_rays;
    out.shadow_rays = t.shadow_rays;
    out.shading_points = t.shading_points;
    return out;
}

// A finished (or cancelled) job's images, each pixel the mean of its samples.
struct ResolvedImages {
    nb::object rgb, albedo, normal, depth, illuminance, samples;
    nb::object aa_level = nb::none(), aa_rays = nb::none();
};

ResolvedImages resolve(const JobHandle& j) {
    const auto& cam = j.job->camera();
    const size_t hgt = cam.height, wid = cam.width;
    float *rgb, *albedo, *normal, *depth, *lux, *samples;
    const size_t s3[3] = {hgt, wid, 3}, s2[2] = {hgt, wid};
    ResolvedImages out;
    out.rgb = nb::cast(new_array<float, 3>(s3, &rgb));
    out.albedo = nb::cast(new_array<float, 3>(s3, &albedo));
    out.normal = nb::cast(new_array<float, 3>(s3, &normal));
    out.depth = nb::cast(new_array<float, 2>(s2, &depth));
    out.illuminance = nb::cast(new_array<float, 2>(s2, &lux));
    out.samples = nb::cast(new_array<float, 2>(s2, &samples));
    {
        nb::gil_scoped_release release;
        j.job->resolve(rgb, albedo, normal, depth, lux, samples);
    }
    const patina::AaStats& aa = j.job->aa_stats();
    if (!aa.level.empty()) {
        float *level, *rays;
        out.aa_level = nb::cast(new_array<float, 2>(s2, &level));
        out.aa_rays = nb::cast(new_array<float, 2>(s2, &rays));
        for (size_t i = 0; i < hgt * wid; ++i) {
            level[i] = aa.level[i];
            rays[i] = aa.rays[i];
        }
    }
    return out;
}

// A distributed render's tile (python/patina/batch/render_tiles.py): its sums (rows x
// columns x Film::kChannels doubles) and the adaptive sampler's per-pixel level and rays.
using TileSums = nb::ndarray<const double, nb::ndim<3>, nb::c_contig, nb::device::cpu>;
using TileStats = nb::ndarray<const uint8_t, nb::ndim<2>, nb::c_contig, nb::device::cpu>;

nb::dict read_tile(const JobHandle& j, int tile) {
    const patina::TileRect r = j.job->tile_rect(tile);
    const size_t rows = r.y1 - r.y0, cols = r.x1 - r.x0;
    const size_t s3[3] = {rows, cols, patina::Film::kChannels}, s2[2] = {rows, cols};
    double* sums;
    auto a_sums = new_array<double, 3>(s3, &sums);
    nb::dict d;
    if (j.job->aa_stats().level.empty()) {
        j.job->read_tile(tile, sums, nullptr, nullptr);
    } else {
        uint8_t *level, *rays;
        auto a_level = new_array<uint8_t, 2>(s2, &level);
        auto a_rays = new_array<uint8_t, 2>(s2, &rays);
        j.job->read_tile(tile, sums, level, rays);
        d["aa_level"] = a_level;
        d["aa_rays"] = a_rays;
    }
    d["sums"] = a_sums;
    return d;
}

void write_tile(JobHandle& j, int tile, TileSums sums, std::optional<TileStats> level, std::optional<TileStats> rays) {
    const patina::TileRect r = j.job->tile_rect(tile);
    const size_t rows = r.y1 - r.y0, cols = r.x1 - r.x0;
    const auto name = "tile " + std::to_string(tile) + ": ";
    if (sums.shape(0) != rows || sums.shape(1) != cols || sums.shape(2) != patina::Film::kChannels)
        throw std::invalid_argument(name + "sums must have shape (" + std::to_string(rows) + ", " + std::to_string(cols) +
                                    ", " + std::to_string(patina::Film::kChannels) + ")");
    const bool adaptive = !j.job->aa_stats().level.empty();
    if (adaptive != (level.has_value() && rays.has_value()))
        throw std::invalid_argument(name + (adaptive ? "the adaptive sampler's tile needs aa_level and aa_rays"
                                                     : "aa_level and aa_rays are the adaptive sampler's"));
    for (const auto* a : {level ? &*level : nullptr, rays ? &*rays : nullptr})
        if (a && (a->shape(0) != rows || a->shape(1) != cols))
            throw std::invalid_argument(name + "aa_level and aa_rays must have the tile's rows and columns");
    j.job->write_tile(tile, sums.data(), level ? level->data() : nullptr, rays ? rays->data() : nullptr);
}

patina::RenderJob::TileWork render_tiles(JobHandle& j, const std::vector<int>& tiles, int first, int end) {
    nb::gil_scoped_release release;  // other threads render other tiles of the job meanwhile
    return j.job->render_tiles(tiles, first, end);
}

// The radiance cache's counts, documented once for progress() and render_tiles().
template <class T>
void cache_counts(nb::class_<T>& c) {
    c.def_ro("cache_points", &T::cache_points, "the radiance cache: cache points built")
        .def_ro("cache_queries", &T::cache_queries, "the radiance cache: first-hit points it served")
        .def_ro("cache_texels_reprojected", &T::cache_texels_reprojected,
                "the radiance cache: texels of those points' hemispheres reprojected (or known empty)")
        .def_ro("cache_texels_traced", &T::cache_texels_traced, "the radiance cache: texels traced");
}

void bind_results(nb::module_& m) {
    auto progress = nb::class_<patina::RenderProgress>(m, "RenderProgress", "A running job's progress (RenderJob.progress()).")
        .def_ro("items_done", &patina::RenderProgress::items_done, "work items (a pass of a tile) finished")
        .def_ro("items_total", &patina::RenderProgress::items_total, "work items in the render")
        .def_ro("rays", &patina::RenderProgress::rays, "rays traced so far (camera, bounce and shadow)")
        .def_ro("samples_done", &patina::RenderProgress::samples_done, "camera samples finished")
        .def_ro("seconds", &patina::RenderProgress::seconds, "seconds since start() (at the last item: the render's time)")
        .def_ro("finished", &patina::RenderProgress::finished, "every work item done")
        .def_ro("cancelled", &patina::RenderProgress::cancelled, "cancel() was called")
        .def_ro("preparing", &patina::RenderProgress::preparing,
                "the adaptive sampler's geometric pre-pass runs (before the first work item)");
    cache_counts(progress);
    using Work = patina::RenderJob::TileWork;
    auto work = nb::class_<Work>(m, "TileWork", "What RenderJob.render_tiles() did.")
        .def_ro("rays", &Work::rays, "rays traced")
        .def_ro("samples", &Work::samples, "camera samples taken");
    cache_counts(work);
    nb::class_<ResolvedImages>(m, "ResolvedImages", "A job's images (RenderJob.resolve()), each pixel the mean of its samples.")
        .def_ro("rgb", &ResolvedImages::rgb, "(H, W, 3) radiance, W/(m^2 sr)")
        .def_ro("albedo", &ResolvedImages::albedo, "(H, W, 3) the first hit's albedo estimate (0 on a miss)")
        .def_ro("normal", &ResolvedImages::normal, "(H, W, 3) the first hit's world-space shading normal (0 on a miss)")
        .def_ro("depth", &ResolvedImages::depth, "(H, W) distance to the first hit, inf where nothing was hit")
        .def_ro("illuminance", &ResolvedImages::illuminance, "(H, W) illuminance at the first hit, lux")
        .def_ro("samples", &ResolvedImages::samples, "(H, W) samples each pixel got")
        .def_ro("aa_level", &ResolvedImages::aa_level, "(H, W) adaptive: the level (1-3) each pixel reached; else None")
        .def_ro("aa_rays", &ResolvedImages::aa_rays, "(H, W) adaptive: the pixel's own rays a pass; else None");
    nb::class_<StageSeconds>(m, "StageSeconds", "Where a job's time went (RenderJob.stage_times(), after wait()).")
        .def_ro("stages", &StageSeconds::stages, "seconds per integrator stage, summed over the threads, in stage order")
        .def_ro("item_seconds", &StageSeconds::item_seconds, "the threads' seconds in work items (stages, sampler, film)")
        .def_ro("camera_rays", &StageSeconds::camera_rays, "camera rays traced")
        .def_ro("secondary_rays", &StageSeconds::secondary_rays, "bounce rays traced")
        .def_ro("shadow_rays", &StageSeconds::shadow_rays, "shadow rays traced")
        .def_ro("shading_points", &StageSeconds::shading_points, "shading points evaluated");
}

}  // namespace

void bind_render_job(nb::module_& m) {
    bind_options(m);
    bind_results(m);
    nb::class_<JobHandle>(m, "RenderJob", "A render running on worker threads: start, poll progress, cancel, resolve.")
        .def(nb::new_(&make_job), nb::arg("scene"), nb::arg("options"))
        .def("start", [](JobHandle& j) { j.job->start(); })
        .def("cancel", [](JobHandle& j) { j.job->cancel(); })
        .def("wait",
             [](JobHandle& j) {
                 nb::gil_scoped_release release;
                 j.job->wait();
             })
        .def("progress", [](const JobHandle& j) { return j.job->progress(); })
        .def("stage_times", &stage_times, "After wait(): where the time went.")
        .def("resolve", &resolve, "After wait(): the images.")
        // a distributed render's tiles (render/render_job.h); on a job that is not started
        .def_prop_ro("tile_count", [](const JobHandle& j) { return j.job->tile_count(); })
        .def_prop_ro("pass_count", [](const JobHandle& j) { return j.job->pass_count(); })
        .def(
            "tile_rect",
            [](const JobHandle& j, int tile) {
                const patina::TileRect r = j.job->tile_rect(tile);
                return nb::make_tuple(r.x0, r.y0, r.x1, r.y1);
            },
            nb::arg("tile"), "(x0, y0, x1, y1): the tile's pixels [x0, x1) x [y0, y1)")
        .def("render_tiles", &render_tiles, nb::arg("tiles"), nb::arg("first"), nb::arg("end"),
             "passes [first, end) of each tile on this thread, added to their sums")
        .def("read_tile", &read_tile, nb::arg("tile"), "the tile's sums (and the adaptive sampler's aa_level, aa_rays)")
        .def("write_tile", &write_tile, nb::arg("tile"), nb::arg("sums"), nb::arg("aa_level").none() = nb::none(),
             nb::arg("aa_rays").none() = nb::none(), "sets the tile's sums (as read_tile gave them)");
}

}  // namespace patina_py
