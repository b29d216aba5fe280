// The buffers of one hemisphere's integration against a member's BRDF (add_cached_indirect,
// cache_stages_impl.h), reused for each member, and the results: each member's indirect
// light. split_narrow_lobes draws its BRDF samples through the same buffers.
#pragma once

#include <vector>

#include "core/simd/target.h"

PATINA_BEGIN_TARGET
namespace cache {

struct HemisphereIntegration {
    std::vector<float> member_light;  // each member's indirect light (RGB)
    // the texels with light: their local directions and radiance (RGB), listed once a hemisphere
    std::vector<float> lit_directions, lit_radiance;
    // the material's inputs for a batch of directions: view directions (the member's, repeated),
    // relative indices, and the three uniforms of each BRDF sample (lobe pick, then the direction)
    std::vector<float> views, etas, u_pick, uniform_u, uniform_v;
    std::vector<float> bsdf_values, pdfs;  // the material's value (RGB) and density per direction
    std::vector<float> lobe_directions;    // a narrow lobe's sampled directions
    std::vector<float> split_weights;      // split_narrow_lobes: each ray's f cos / (pdf K), RGB
};

}  // namespace cache
PATINA_END_TARGET
