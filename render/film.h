// The image being rendered: per-pixel sums of weighted samples (radiance and AOVs) and
// their weights. Tiles own disjoint pixels, so a tile's sampler adds without locks.
#pragma once

#include <cstddef>
#include <vector>

#include "render/integrator.h"

namespace patina {

class Film {
public:
    Film(int width, int height);
    int width() const { return m_width; }
    int height() const { return m_height; }
    // Adds one sample's result to a pixel with a filter weight.
    void add(int pixel, const PathResult& r, float weight);
    // Each pixel the weighted mean of its samples (H x W x 3 etc.); samples: the weight sum.
    void resolve(float* rgb, float* albedo, float* normal, float* depth, float* lux, float* samples) const;

private:
    int m_width, m_height;
    std::vector<double> m_rgb, m_albedo, m_normal, m_lux, m_depth, m_weight, m_depth_weight;
};

}  // namespace patina
