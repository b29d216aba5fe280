// A luminaire as the exact direct illuminance sums it (render/lighting/direct_illuminance.h):
// a point, a spot or a goniometric (IES / EULUMDAT) luminaire, in candela. The lighting
// calculations hand it over themselves (python/patina/lighting/direct.py) rather than as the
// renderer's Light (a radiometric colour, a place in the light selection); the shape of its
// intensity is the renderer's spot and goniometric kinds', evaluated by the renderer's own
// functions (source_intensity_impl.h).
#pragma once

#include <cstdint>

#include "render/lights/goniometric_light.h"
#include "render/lights/spot_light.h"

namespace patina {

enum class SourceKind : uint8_t { Point, Spot, Goniometric };

struct DirectSource {
    SourceKind kind = SourceKind::Point;
    float position[3] = {0, 0, 0};
    float scale = 1;  // candela per unit of the relative intensity (point, spot) or of the candela table
    // the shape of its intensity as the renderer's light kinds hold it, so that both evaluate
    // it by one function (render/lights/delta_intensity_impl.h, relative_intensity): spot, its
    // unit beam axis (`direction`) and the cosines of the half-angles where the cone starts to
    // fade (inner) and where it is dark (outer); goniometric, the luminaire's unit axes in the
    // world (docs/luminaires.md), its photometric type (B, else C) and its candela table over
    // (C, gamma) or (H, V), radians. Their position and colour are not read here.
    SpotLight spot{};
    GoniometricLight goniometric{};
};

}  // namespace patina
