// A luminaire as the exact direct illuminance sums it (render/lighting/direct_illuminance.h):
// a point, a spot or a goniometric (IES / EULUMDAT) luminaire, in candela. The lighting
// calculations hand it over themselves (python/patina/lighting/direct.py) rather than reading
// the renderer's Light, so that the renderer's light kinds and the lighting calculations can
// change apart; the intensities are the renderer's all the same (source_intensity_impl.h).
#pragma once

#include <cstdint>

#include "render/lights/grid2.h"

namespace patina {

enum class SourceKind : uint8_t { Point, Spot, Goniometric };

struct DirectSource {
    SourceKind kind = SourceKind::Point;
    float position[3] = {0, 0, 0};
    float scale = 1;  // candela per unit of the relative intensity (point, spot) or of the candela table
    // spot: the unit beam axis, the cosines of the half-angles where the cone starts to fade
    // (inner) and where it is dark (outer)
    float axis[3] = {0, -1, 0};
    float cos_inner = 1, cos_outer = 1;
    // goniometric: the luminaire's unit axes in the world (docs/luminaires.md), its photometric
    // type (B, else C) and its candela table over (C, gamma) or (H, V), radians
    float axis_x[3] = {1, 0, 0}, axis_y[3] = {0, 1, 0}, axis_z[3] = {0, 0, 1};
    bool type_b = false;
    Grid2View candela{};
};

}  // namespace patina
