// One query's reprojections (reconstruct_hemispheres, radiance_cache_impl.h): its own cache
// point's, and where that leaves holes, its second cache point's (fill_holes), with the work
// arrays the reprojection reuses from point to point.
#pragma once

#include <vector>

#include "core/simd/target.h"
#include "render/cache/bit_mask.h"
#include "render/cache/reprojection_impl.h"

PATINA_BEGIN_TARGET
namespace cache {

struct QueryReprojection {
    ReprojectScratch scratch;
    Reprojection from_assigned;  // the query's own cache point reprojected
    Reprojection from_second;    // its second cache point's (fill_holes)
    BitMask128 holes_around;     // the texels the second cache point is wanted in (fill_holes)
    std::vector<float> second_texture;  // the second cache point's reprojected texture (R^2 x 3)
};

}  // namespace cache
PATINA_END_TARGET
