// Importance sampling of an RGL material by its own warps (Dupuy & Jakob 2018, section 5;
// Mitsuba 3's `measured`): a uniform point is warped by the luminance warp (where the
// reflected energy is) and then by the VNDF warp (to a microfacet normal m), both given the
// incident angles; wo is wi reflected about m. Its pdf is what rgl_pdf_batch returns for
// the same pair, up to float rounding.
#pragma once

#include "brdf/rgl/rgl_view.h"
#include "core/vec3.h"

namespace patina {

struct RglSample {
    Vec3f wo;
    float pdf;  // per steradian; 0 when wi or the sampled wo is below the horizon
};

// u1, u2 uniform in [0, 1); wi a unit direction in the surface's frame (z = normal).
RglSample rgl_sample(const RglView& v, const Vec3f& wi, float u1, float u2);

}  // namespace patina
