// The triangles light (disks, spheres, emissive meshes): the scene's triangles of an emitter
// material, of uniform radiance (render/lights/area_light.h), sampled by their area cdf.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/lights/area_light.h"

namespace patina {

struct TriangleLight : AreaLight {
    std::vector<int32_t> triangles;  // scene triangle ids
    std::vector<float> area_cdf;     // size + 1 values, 0 .. 1
    // area: the triangles' total

    // Centred on the area-weighted centroid (triangle_vertices: the scene's, 9 floats each).
    LightSelection selection(float small2, const float* triangle_vertices) const {
        double c[3] = {0, 0, 0}, prev = 0;
        for (size_t t = 0; t < triangles.size(); ++t) {
            const float* v = triangle_vertices + 9 * static_cast<size_t>(triangles[t]);
            const double w = area_cdf[t + 1] - prev;
            prev = area_cdf[t + 1];
            for (int k = 0; k < 3; ++k) c[k] += w * (v[k] + v[3 + k] + v[6 + k]) / 3;
        }
        const float center[3] = {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2])};
        return selection_at(center, small2);
    }
};

}  // namespace patina
