// Where a tile's camera samples go, and how their results become pixels.
//
// The render job hands each (tile, pass) work item to a PixelSampler: begin(), then
// next_batch() / take_results() in rounds until next_batch() has nothing more. The uniform
// sampler below shoots a fixed number of jittered samples per pixel in one or more rounds
// and box-filters them; the adaptive antialiasing (render/antialiasing/adaptive_sampler.h, thesis
// chapter 3) implements the same interface, deciding each round's positions from the
// previous round's results.
#pragma once

#include <cstdint>
#include <vector>

#include "render/camera/film.h"
#include "render/integrators/integrator.h"

namespace patina {

struct TileRect {
    int x0, y0, x1, y1;  // pixels [x0, x1) x [y0, y1)
};

inline constexpr int kUniformTileSize = 16;  // the render job's tiles for the uniform sampler

class PixelSampler {
public:
    virtual ~PixelSampler() = default;
    virtual void begin(const TileRect& tile, int pass) = 0;
    // The next round's camera samples; false (and no samples) when the work item is done.
    virtual bool next_batch(std::vector<CameraSample>& samples) = 0;
    // The results of the round just traced, in the order of its samples.
    virtual void take_results(const CameraSample* samples, const PathResult* results, size_t n) = 0;
    // Rays the sampler traced itself to decide where to sample (the adaptive sampler's
    // signal), since construction; the integrator's rays are counted by its scratch.
    virtual size_t rays_traced() const { return 0; }
};

// Samples [pass_begin[p], pass_begin[p + 1]) of every pixel, box-filtered, at positions
// within the pixel from the sampler's first two dimensions (Sobol: stratified, a (0, 2)-
// sequence; independent: uniform), drawn N at a time by the kernels' jitter_pixel_positions.
// Pixels go in Morton order, each pixel's samples of a round side by side; a round holds at
// most max_batch samples.
class UniformSampler final : public PixelSampler {
public:
    UniformSampler(Film& film, const RenderKernels& kernels, uint32_t seed, SamplerKind kind,
                   std::vector<int> pass_begin, size_t max_batch = 4096);
    void begin(const TileRect& tile, int pass) override;
    bool next_batch(std::vector<CameraSample>& samples) override;
    void take_results(const CameraSample* samples, const PathResult* results, size_t n) override;

private:
    Film& m_film;
    const RenderKernels& m_kernels;
    uint32_t m_seed;
    SamplerKind m_kind;
    std::vector<int> m_pass_begin;
    size_t m_max_batch;
    std::vector<int> m_pixels;  // the tile's pixels in Morton order
    std::vector<CameraSample> m_corners;  // theirs: top-left corner (fx, fy) and stream key; index 0
    std::vector<std::pair<uint32_t, int>> m_order;  // begin()'s sort, its memory kept
    int m_next_sample = 0, m_end_sample = 0;
    int m_round_samples = 1;  // each pixel's samples in the last round
};

}  // namespace patina
