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

void FilmSum::add(const PathResult& r, float w) {
    for (int k = 0; k < 3; ++k) {
        rgb[k] += w * r.rgb[k];
        albedo[k] += w * r.albedo[k];
        normal[k] += w * r.normal[k];
    }
    lux += w * r.illuminance;
    if (std::isfinite(r.depth)) {
        depth += w * r.depth;
        depth_weight += w;
    }
    weight += w;
}

void Film::add(int pixel, const FilmSum& s) {
    for (int k = 0; k < 3; ++k) {
        m_rgb[3 * pixel + k] += s.rgb[k];
        m_albedo[3 * pixel + k] += s.albedo[k];
        m_normal[3 * pixel + k] += s.normal[k];
    }
    m_lux[pixel] += s.lux;
    m_depth[pixel] += s.depth;
    m_depth_weight[pixel] += s.depth_weight;
    m_weight[pixel] += s.weight;
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

namespace {

// Both directions walk the same channel order, so read() then write() restores a pixel exactly.
template <class F>
void for_each_channel(int width, int x0, int y0, int x1, int y1, F&& f) {
    size_t k = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const size_t i = static_cast<size_t>(y) * width + x;
            for (int c = 0; c < 3; ++c) f(k++, 0, 3 * i + c);
            for (int c = 0; c < 3; ++c) f(k++, 1, 3 * i + c);
            for (int c = 0; c < 3; ++c) f(k++, 2, 3 * i + c);
            f(k++, 3, i);
            f(k++, 4, i);
            f(k++, 5, i);
            f(k++, 6, i);
        }
}

}  // namespace

void Film::read(int x0, int y0, int x1, int y1, double* out) const {
    const std::vector<double>* ch[7] = {&m_rgb, &m_albedo, &m_normal, &m_lux, &m_depth, &m_weight, &m_depth_weight};
    for_each_channel(m_width, x0, y0, x1, y1, [&](size_t k, int c, size_t i) { out[k] = (*ch[c])[i]; });
}

void Film::write(int x0, int y0, int x1, int y1, const double* in) {
    std::vector<double>* ch[7] = {&m_rgb, &m_albedo, &m_normal, &m_lux, &m_depth, &m_weight, &m_depth_weight};
    for_each_channel(m_width, x0, y0, x1, y1, [&](size_t k, int c, size_t i) { (*ch[c])[i] = in[k]; });
}

}  // namespace patina
