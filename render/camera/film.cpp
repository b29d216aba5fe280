#include "render/camera/film.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace patina {

Film::Film(int width, int height)
    : m_width(width), m_height(height), m_sums(kChannels * static_cast<size_t>(width) * height, 0.0) {}

void Film::resolve(float* rgb, float* albedo, float* normal, float* depth, float* lux, float* samples) const {
    const size_t pixels = static_cast<size_t>(m_width) * m_height;
    for (size_t i = 0; i < pixels; ++i) {
        const double* p = &m_sums[kChannels * i];
        const double inv = p[kWeight] > 0 ? 1.0 / p[kWeight] : 0.0;
        for (int k = 0; k < 3; ++k) {
            rgb[3 * i + k] = static_cast<float>(p[kRgb + k] * inv);
            albedo[3 * i + k] = static_cast<float>(p[kAlbedo + k] * inv);
        }
        const double* n = p + kNormal;
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; ++k) normal[3 * i + k] = len > 0 ? static_cast<float>(n[k] / len) : 0.0f;
        depth[i] = p[kDepthWeight] > 0 ? static_cast<float>(p[kDepth] / p[kDepthWeight])
                                       : std::numeric_limits<float>::infinity();
        lux[i] = static_cast<float>(p[kLux] * inv);
        samples[i] = static_cast<float>(p[kWeight]);
    }
}

// The film keeps a pixel's sums in read()'s channel order: a row of the rectangle is one copy.
void Film::read(int x0, int y0, int x1, int y1, double* out) const {
    for (int y = y0; y < y1; ++y, out += kChannels * static_cast<size_t>(x1 - x0)) {
        const double* row = &m_sums[kChannels * (static_cast<size_t>(y) * m_width + x0)];
        std::copy(row, row + kChannels * static_cast<size_t>(x1 - x0), out);
    }
}

void Film::write(int x0, int y0, int x1, int y1, const double* in) {
    for (int y = y0; y < y1; ++y, in += kChannels * static_cast<size_t>(x1 - x0))
        std::copy(in, in + kChannels * static_cast<size_t>(x1 - x0),
                  &m_sums[kChannels * (static_cast<size_t>(y) * m_width + x0)]);
}

}  // namespace patina
