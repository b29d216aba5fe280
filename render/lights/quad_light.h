// The quad light: a parallelogram of uniform radiance (render/lights/area_light.h), corners
// centre +- u +- v.
#pragma once

#include "render/lights/area_light.h"

namespace patina {

struct QuadLight : AreaLight {
    float center[3] = {0, 0, 0};
    float u[3] = {1, 0, 0}, v[3] = {0, 0, 1};  // half-edge vectors
    float normal[3] = {0, -1, 0};               // unit, normalize(cross(u, v)); emits on this side
    // area = 4 |u x v|
    LightSelection selection(float small2, const float*) const { return selection_at(center, small2); }
};

}  // namespace patina
