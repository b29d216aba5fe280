// A luminaire's candela towards N unit directions from it (render/lighting/direct_source.h):
// a point's constant, a spot's smoothstep cone, a goniometric luminaire's candela table by
// photometric type C or B -- the renderer's own relative intensity of its spot and
// goniometric light kinds (render/lights/delta_intensity_impl.h), scaled to candela, so the
// lux of the lighting calculations and the light of a render agree bit for bit.
#pragma once

#include "core/simd/kernel_width.h"
#include "render/lighting/direct_source.h"
#include "render/lights/delta_intensity_impl.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// `out`: unit, from the luminaire.
PATINA_INLINE F source_candela(const DirectSource& s, const V3& out) {
    switch (s.kind) {
        case SourceKind::Spot: return F(s.scale) * relative_intensity<N>(s.spot, out);
        case SourceKind::Goniometric: return F(s.scale) * relative_intensity<N>(s.goniometric, out);
        default: return F(s.scale);
    }
}

}  // namespace render_detail
PATINA_END_TARGET
