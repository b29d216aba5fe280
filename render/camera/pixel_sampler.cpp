#include "render/camera/pixel_sampler.h"

#include <algorithm>
#include <utility>

#include "render/samplers/rng.h"

namespace patina {
namespace {

// Interleaves the bits of x and y: pixels in Morton order, so neighbouring paths (one
// SIMD packet) look through neighbouring pixels.
uint32_t morton(uint32_t x, uint32_t y) {
    uint32_t m = 0;
    for (int b = 0; b < 16; ++b) m |= ((x >> b) & 1u) << (2 * b) | ((y >> b) & 1u) << (2 * b + 1);
    return m;
}

}  // namespace

UniformSampler::UniformSampler(Film& film, const RenderKernels& kernels, uint32_t seed, SamplerKind kind,
                               std::vector<int> pass_begin, size_t max_batch)
    : m_film(film),
      m_kernels(kernels),
      m_seed(seed),
      m_kind(kind),
      m_pass_begin(std::move(pass_begin)),
      m_max_batch(max_batch) {}

void UniformSampler::begin(const TileRect& tile, int pass) {
    m_order.clear();
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x)
            m_order.push_back({morton(x - tile.x0, y - tile.y0), y * m_film.width() + x});
    std::sort(m_order.begin(), m_order.end());
    m_pixels.clear();
    m_corners.clear();
    const int width = m_film.width();
    for (const auto& [code, pixel] : m_order) {
        m_pixels.push_back(pixel);
        // each pixel one stream, its samples in order (Sobol: one sequence a pixel)
        m_corners.push_back({static_cast<float>(pixel % width), static_cast<float>(pixel / width),
                             stream_key(m_seed, static_cast<uint32_t>(pixel)), 0});
    }
    m_next_sample = m_pass_begin[pass];
    m_end_sample = m_pass_begin[pass + 1];
}

bool UniformSampler::next_batch(std::vector<CameraSample>& samples) {
    samples.clear();
    if (m_next_sample >= m_end_sample || m_pixels.empty()) return false;
    const int per_round = std::max<int>(1, static_cast<int>(m_max_batch / m_pixels.size()));
    const int s1 = std::min(m_end_sample, m_next_sample + per_round);
    const size_t np = m_corners.size();
    m_round_samples = s1 - m_next_sample;
    samples.resize(np * static_cast<size_t>(m_round_samples));
    // pixel by pixel, each pixel's samples side by side: a packet of camera rays then looks
    // through one pixel (coherent: the same few triangles, the same texels of a map), and
    // each pixel still gets its samples in order
    CameraSample* out = samples.data();
    for (const CameraSample& corner : m_corners)
        for (int s = m_next_sample; s < s1; ++s, ++out) {
            *out = corner;
            out->index = static_cast<uint32_t>(s);
        }
    m_kernels.jitter_pixel_positions(m_kind, samples.data(), samples.size());
    m_next_sample = s1;
    return true;
}

void UniformSampler::take_results(const CameraSample* samples, const PathResult* results, size_t n) {
    // a box filter: every sample adds to the pixel it was shot through, in sample order (the
    // round's samples are each pixel's in order, pixel after pixel; the pixel is not
    // recomputed from fx, fy, which round up to the next pixel at the far edge of a pixel of
    // a wide image)
    (void)samples;
    const size_t per_pixel = static_cast<size_t>(m_round_samples);
    for (size_t p = 0, q = 0; q < n; ++p)
        for (size_t k = 0; k < per_pixel && q < n; ++k, ++q) m_film.add(m_pixels[p], results[q], 1.0f);
}

}  // namespace patina
