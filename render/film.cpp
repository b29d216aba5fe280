#include "render/film.h"

#include <cmath>
#include <limits>

namespace patina {

Film::Film(int width, int height) : m_width(width), m_height(height) {
    const size_t pixels = static_cast<size_t>(width) * height;
    m_rgb.assign(3 * pixels, 0.0);
    m_albedo.assign(3 * pixels, 0.0);
    m_normal.assign(3 * pixels, 0.0);
    m_lux.assign(pixels, 0.0);
    m_depth.assign(pixels, 0.0);
    m_weight.assign(pixels, 0.0);
    m_depth_weight.assign(pixels, 0.0);
}

void Film::add(int pixel, const PathResult& r, float weight) {
    for (int k = 0; k < 3; ++k) {
        m_rgb[3 * pixel + k] += weight * r.rgb[k];
        m_albedo[3 * pixel + k] += weight * r.albedo[k];
        m_normal[3 * pixel + k] += weight * r.normal[k];
    }
    m_lux[pixel] += weight * r.illuminance;
    if (std::isfinite(r.depth)) {
        m_depth[pixel] += weight * r.depth;
        m_depth_weight[pixel] += weight;
    }
    m_weight[pixel] += weight;
}

void Film::resolve(float* rgb, float* albedo, float* normal, float* depth, float* lux, float* samples) const {
    const size_t pixels = m_weight.size();
    for (size_t i = 0; i < pixels; ++i) {
        const double inv = m_weight[i] > 0 ? 1.0 / m_weight[i] : 0.0;
        for (int k = 0; k < 3; ++k) {
            rgb[3 * i + k] = static_cast<float>(m_rgb[3 * i + k] * inv);
            albedo[3 * i + k] = static_cast<float>(m_albedo[3 * i + k] * inv);
        }
        const double* n = &m_normal[3 * i];
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; ++k) normal[3 * i + k] = len > 0 ? static_cast<float>(n[k] / len) : 0.0f;
        depth[i] = m_depth_weight[i] > 0 ? static_cast<float>(m_depth[i] / m_depth_weight[i])
                                         : std::numeric_limits<float>::infinity();
        lux[i] = static_cast<float>(m_lux[i] * inv);
        samples[i] = static_cast<float>(m_weight[i]);
    }
}

}  // namespace patina
