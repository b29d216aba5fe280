// The adaptive coherent antialiasing of thesis chapter 3 as a PixelSampler
// (docs/antialiasing.md; the fixed positions, zone table and weights: render/antialiasing/adaptive_pattern.h).
//
// A (tile, pass) work item takes up to three rounds:
//   1. the tile's (w + 1) x (h + 1) pixel corners, each traced once and shared by the
//      pixels around it; each pixel is classified: no discontinuity (the mean of its
//      corners, done), horizontal (high contrast A-B or C-D; also when ambiguous) or
//      vertical (the pattern rotated 90 degrees counter-clockwise); a pixel that a visible
//      feature edge of the geometric pre-pass crosses (render/antialiasing/edge_hints.h) is refined even
//      when its corners agree;
//   2. E, F, G, H of every discontinuous pixel (one packet of four), then the three fours
//      of comparisons give a 4-bit mask each, and the zone table the zones to refine; a
//      pixel whose edges the pre-pass placed in one run of up to three zones skips this
//      round: those zones are refined at once (weights: aa::kDirectWeights);
//   3. one zigzag of four through each flagged zone (at most five a pixel), the zones the
//      pre-pass's edges cross included; a pixel the pre-pass finds crowded (edges in four
//      zones or more, nearer each other than the pixel shows) traces zones 1 and 3 only.
// Every position's integrator sample is added with its precomputed weight. A pixel that a
// sub-pixel highlight of the pre-pass falls on (render/antialiasing/highlights.h) also traces, in round 1,
// a grid of rays over the highlight's piece, which stands for the piece's area in place of
// the pattern's rays inside it.
//
// The decisions are not taken on the integrator's noisy radiance but on a signal that is a
// function of the position only: each position traced again by the direct-light integrator
// with one random-number key shared by every position of the image (the same light sample,
// BRDF sample and lens point everywhere), giving whether the camera ray hits, the first
// hit's depth and shading normal, and the radiance of that one light sample through the
// material's BRDF (highlights included). A flat region, however noisy its radiance, gives
// equal signals and stays at level 1; the pattern is the same in every pass and for any
// thread count or SIMD width. So the first pass's decisions are kept (AaStats::pattern): a
// later pass of the tile traces the same positions, without the signal or the comparisons.
//
// Where the integrator's own sample is already such a function of the position (direct
// light from one delta light through a pinhole, nothing random left: aa_sample_is_signal),
// the sample is the signal and nothing is traced twice.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "render/antialiasing/adaptive_pattern.h"
#include "render/antialiasing/edge_hints.h"
#include "render/antialiasing/signal_lanes.h"
#include "render/camera/film.h"
#include "render/camera/pixel_sampler.h"
#include "render/integrators/integrator.h"
#include "render/scene.h"

namespace patina {

// The render job's tiles for the adaptive sampler: 32 x 32 pixels against 16 x 16 cut the
// integrator's time a camera ray by 10-14 % (its rounds of scattered refined pixels are
// larger wavefronts) and trace fewer corners twice (docs/antialiasing.md, "Measured").
inline constexpr int kAdaptiveTileSize = 32;
inline constexpr float kDefaultAaThreshold = 0.15f;  // docs/antialiasing.md, "Measured": why 0.15

// What decides refinement at one position.
struct AaSignal {
    float colour[3];  // the radiance of the shared-key direct-light trace (a miss: the environment seen)
    float normal[3];
    float depth;      // inf: a miss
};

// The contrast of two signals, in [0, 1]: the largest over
//   r, g, b of the colour:  |a - b| / (a + b)   (relative: the same in dark and bright regions)
//   the depth:              |a - b| / (a + b)
//   the normal:             (1 - a . b) / 2
// and 1 where one ray hits and the other does not. Refine where it exceeds the threshold.
float aa_contrast(const AaSignal& a, const AaSignal& b);
// aa_contrast(a, b) > threshold with its divisions multiplied out: the sampler's comparisons
// (inline: two to fourteen a pixel). Every test is evaluated and the outcomes combined
// without branches: which of them decides is data (an edge or not), and its mispredicted
// branches cost more than the few tests skipped.
inline bool aa_differs(const AaSignal& a, const AaSignal& b, float threshold) {
    const bool ha = std::isfinite(a.depth), hb = std::isfinite(b.depth);
    const bool broken = 1.0f > threshold;  // what a contrast of 1 decides
    // |x - y| / (|x| + |y|) > threshold, multiplied out
    const auto step = [&](float x, float y) {
        const bool finite = std::isfinite(x) & std::isfinite(y);
        return finite ? std::fabs(x - y) > threshold * (std::fabs(x) + std::fabs(y)) : broken;
    };
    const bool colour = step(a.colour[0], b.colour[0]) | step(a.colour[1], b.colour[1]) | step(a.colour[2], b.colour[2]);
    const float d = a.normal[0] * b.normal[0] + a.normal[1] * b.normal[1] + a.normal[2] * b.normal[2];
    const bool normal = std::isfinite(d) ? 0.5f * (1.0f - std::clamp(d, -1.0f, 1.0f)) > threshold : broken;
    const bool surface = step(a.depth, b.depth) | normal;  // both hit (a miss's depth is inf)
    return ha != hb ? broken : colour | (ha & surface);
}

// Whether the integrator's sample at a position is the same for every random-number key,
// so it can serve as the signal: direct light only (max_depth 1), a pinhole camera, one
// light and that a delta light (point, spot, goniometric: no choice between lights, no
// point on an area), no environment and no emitting surface for the BRDF-sampled ray to
// find. Then the only random numbers left pick the BRDF-sampled direction, whose ray can
// reach nothing that emits.
bool aa_sample_is_signal(const RenderScene& scene, const IntegratorSettings& integrator);

// Per-pixel outcome of the first pass (the pattern is the same in every pass).
struct AaStats {
    std::vector<uint8_t> level;  // 1, 2 or 3 (0: not rendered yet)
    std::vector<uint8_t> rays;   // the pixel's own rays: 1 (its share of the corners) + 4 (level 2) + 4 a zigzag
    // The decisions of the first pass this job rendered of the pixel's tile, kept for its
    // later passes (aa_pattern_code; 0: none yet, so decided anew). Empty: none kept.
    std::vector<uint16_t> pattern;
};

// A pixel's decisions: its level-3 zones (bits 0-4), the rotated pattern (bit 5), its level
// 1-3 (bits 6-7, so a decided pixel is never 0) and whether it skipped level 2 (bit 8).
inline uint16_t aa_pattern_code(int level, bool vertical, uint8_t zones, bool direct) {
    return static_cast<uint16_t>((direct ? 1 << 8 : 0) | level << 6 | (vertical ? 1 << 5 : 0) | zones);
}

class AdaptiveSampler : public PixelSampler {
public:
    // hints: the geometric pre-pass (render/antialiasing/edge_hints.h), or nullptr for none
    AdaptiveSampler(Film& film, const RenderScene& scene, const RenderKernels& kernels,
                    const IntegratorSettings& integrator, uint32_t seed, float threshold, AaStats& stats,
                    const AaEdgeHints* hints = nullptr);
    void begin(const TileRect& tile, int pass) override;
    bool next_batch(std::vector<CameraSample>& samples) override;
    void take_results(const CameraSample* samples, const PathResult* results, size_t n) override;
    size_t rays_traced() const override { return m_signal_scratch.rays_traced; }

protected:
    // The signal's trace of a round's positions (samples carry the shared key); a test
    // overrides it to feed a known signal.
    virtual void trace_signal(const CameraSample* samples, size_t n, PathResult* out);

private:
    struct PixelState {
        int pixel;              // index in the image
        int tile_x, tile_y;     // position in the tile
        bool vertical = false;  // the pattern is rotated
        uint8_t zones = 0;      // level-3 zones
        uint8_t hint = 0;       // the zones a visible feature edge crosses (the geometric pre-pass)
        bool direct = false;    // level 2 skipped: the hint's one run of zones refined at once
        int level = 1;
        int first = -1;         // index of its level-2 (then level-3) results in m_refined
        int spot = -1;          // its highlight piece in m_hints->spots (render/antialiasing/highlights.h), -1 none
        int spot_first = -1;    // index of its spot grid's results in m_spot
    };
    // the traces whose results are a round's signals: its own results where they are the
    // signal, else the positions traced again with the shared key
    const PathResult* signal_results(const CameraSample* samples, const PathResult* results, size_t n);
    void place(const PixelState& p, int s, float& fx, float& fy) const;
    int corner_of(const PixelState& p, int canonical) const;  // index into m_corners
    AaSignal corner_signal(int corner) const;                   // gathered from m_corner_lanes
    void finish(const PathResult* level3);  // level3: round 3's results (nullptr: none traced)
    void classify_corners();       // round 1: each pixel's level and orientation from its corners
    void queue_refinement(int i);  // a refined pixel into round 2, or round 3 at once (level 2 skipped)
    void refine_level2(const PathResult* signal, size_t n);  // round 2: each level-2 pixel's zones from E-H
    void recall_pattern();         // a later pass: the decisions kept from the first
    void record_pixel(const PixelState& p, bool stats);  // its decisions kept; stats: its level and rays too
    bool in_spot(const PixelState& p, int s) const;  // sample s of p's pattern lies in its highlight piece

    Film& m_film;
    const RenderScene& m_scene;
    const RenderKernels& m_kernels;
    uint32_t m_seed;
    float m_threshold;
    AaStats& m_stats;
    bool m_sample_is_signal;
    const AaEdgeHints* m_hints;
    PathScratch m_signal_scratch;

    TileRect m_tile{};
    int m_pass = 0, m_round = 0;
    bool m_recalled = false;  // this item's decisions are the kept ones: no signal, no comparisons
    std::vector<PixelState> m_pixels;  // Morton order
    int m_order_w = -1, m_order_h = -1;  // the tile size the orders below are for
    // the tile's pixels in Morton order, their place in the tile set (the rest is each item's):
    // copied at each item's start instead of a division and a remainder a pixel
    std::vector<PixelState> m_blank_pixels;
    std::vector<int> m_corner_order;   // corner indices (cy * (w + 1) + cx) in Morton order
    std::vector<std::pair<int, int>> m_corner_place;  // the same corners' (cx, cy) in the tile
    std::vector<int> m_row_order;      // m_pixels' indices in the tile's row order (ty * w + tx)
    std::vector<uint8_t> m_across, m_down;  // round 1: neighbouring corners that differ
    std::vector<PathResult> m_corners;
    size_t m_corner_count = 0;          // round 1: the corners, then the highlights' grids
    std::vector<int> m_spot_pixels;     // into m_pixels
    std::vector<PathResult> m_spot;
    AaSignalLanes m_corner_lanes;  // round 1: the corners' signals, channel by channel
    std::vector<int> m_level2_pixels, m_level3_pixels;  // into m_pixels
    std::vector<PathResult> m_level2;
    std::vector<AaSignal> m_level2_signal;
    std::vector<int> m_level3_first;  // per m_pixels entry: its first level-3 result, -1 none
    std::vector<CameraSample> m_signal_samples;  // a round's positions with the signal's key
    std::vector<PathResult> m_signal_out;
};

}  // namespace patina
