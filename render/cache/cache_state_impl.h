// Everything one worker's radiance cache keeps from call to call (memory only, no results),
// as the work items of its stages (docs/radiance-cache.md): the batch's query table, the
// regions' hemispheres it uses, its cache points' placement and building, each query's
// reprojections, the glossy hits' split, the integration of a hemisphere, and cache-guided's
// guides. Kept in the worker's PathScratch (cache_state), made at first use.
#pragma once

#include <memory>
#include <vector>

#include "core/simd/kernel_width.h"
#include "render/cache/cache_point_build.h"
#include "render/cache/concentrated_texels.h"
#include "render/cache/glossy_hit_split.h"
#include "render/cache/guided_bounces_impl.h"
#include "render/cache/hemisphere_integration.h"
#include "render/cache/query_reprojection_impl.h"
#include "render/cache/query_table.h"
#include "render/cache/reprojection_impl.h"
#include "render/cache/stored_hemispheres.h"
#include "render/integrators/integrator.h"
#include "render/integrators/stage_timer.h"

PATINA_BEGIN_TARGET
namespace cache {

struct CacheState {
    PathScratch inner;                        // the path tracer's scratch for the cache's own rays
    std::vector<CameraSample> inner_samples;  // ... and its camera samples
    QueryTable table;                 // collect_queries: the batch's queries and members
    StoredHemispheres stored;         // the regions' hemispheres the members take
    CachePointBuild build;            // place_cache_points, build_cache_points, the rays traced
    TexelDirections texel_directions;  // of the cache's resolution: every stage's texel directions
    QueryReprojection reprojection;   // reconstruct_hemispheres: one query's reprojections
    GlossyHitSplit glossy_split;      // split_glossy_hits: the glossy texel hits' further paths
    TexelRefinement texel_refinement;  // refine_concentrated_texels: the concentrated texels' further paths
    HemisphereIntegration integration;  // add_cached_indirect, split_narrow_lobes: the BRDF buffers
    GuidePool guides;                 // cache-guided: the batch's cache points as guides
    GuideChoices guide_choices;       // cache-guided: which points draw from their guide
    StageTimer* timer = nullptr;      // the worker's: the cache's stages are laps of it
    void lap(Stage stage) {
        if (timer) timer->lap(stage);
    }
};

// The worker's cache state kept in its PathScratch (made at first use, at this width).
inline CacheState& cache_state(PathScratch& scratch) {
    if (!scratch.cache || scratch.cache_width != N) {
        scratch.cache = std::unique_ptr<void, void (*)(void*)>(new CacheState(),
                                                               [](void* p) { delete static_cast<CacheState*>(p); });
        scratch.cache_width = N;
    }
    return *static_cast<CacheState*>(scratch.cache.get());
}

}  // namespace cache
PATINA_END_TARGET
