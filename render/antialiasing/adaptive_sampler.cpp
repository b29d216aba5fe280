#include "render/antialiasing/adaptive_sampler.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "render/samplers/rng.h"

namespace patina {
namespace {

constexpr uint32_t kCornerSalt = 0x6a09e667u;  // corners' random streams apart from the pixels'
constexpr uint32_t kSignalSalt = 0xbb67ae85u;  // the signal's one shared stream
constexpr uint32_t kSpotSalt = 0x3c6ef372u;    // the highlights' grids
constexpr int kSpotRays = kAaSpotGrid * kAaSpotGrid;
// A pixel whose edges the pre-pass placed in one run of up to this many zones skips level 2.
// At 512 x 384 against up to 5: the checkerboard's RMSE 0.00717 -> 0.00622 and the lines'
// 0.00335 -> 0.00311 for 0.06 and 0.03 rays a pixel more (runs of four or five zones are the
// crowded pixels, several edges, where the middle row tells the zigzags' strips apart).
constexpr int kDirectMaxZones = 3;
// A pixel whose hint crosses this many zones or more is crowded: three edges or more cross
// it, nearer each other than the pixel can show (the checkerboard's squares towards the
// horizon, smaller than a pixel), so where its edges lie does not matter, only how much of
// the pixel each side covers. It traces the zigzags of zones 1 and 3 only, eight rays spread
// over the pixel with E..H and the corners, not one zigzag a flagged zone. At 512 x 384 the
// checkerboard's pixels of 25 rays went to 13: 1.995 -> 1.812 rays a pixel, RMSE 0.00622 ->
// 0.00771 (vs 25 random rays 2.41 -> 1.94); zones 0, 2 and 4 cost 0.06 rays a pixel more for
// a larger error (0.00831), zone 2 alone made it 0.00949, and no zigzag 0.01169 (16
// stratified rays' error is lower: docs/antialiasing.md, "Measured").
constexpr int kCrowdedMinZones = 4;
constexpr uint8_t kCrowdedZones = 0b01010;
// finish() asks for the film's sums of the pixel this many ahead in row order: the tile's
// rows are 32 pixels, too short for the hardware's prefetcher, and the film (20 MB at 512 x
// 384) is far from the core
constexpr size_t kFilmLookahead = 4;

uint32_t morton(uint32_t x, uint32_t y) {
    uint32_t m = 0;
    for (int b = 0; b < 16; ++b) m |= ((x >> b) & 1u) << (2 * b) | ((y >> b) & 1u) << (2 * b + 1);
    return m;
}

// |a - b| / (|a| + |b|): scale-free, so a step of 20 % counts the same at 0.01 and at 100
float relative(float a, float b) {
    if (!std::isfinite(a) || !std::isfinite(b)) return 1.0f;  // a broken signal is refined, never trusted
    const float s = std::fabs(a) + std::fabs(b);
    return s > 0 ? std::fabs(a - b) / s : 0.0f;
}

// what decides refinement at a position, from its signal trace (or its own sample)
AaSignal aa_signal(const PathResult& r) {
    // element by element: std::copy of three floats was a call of memmove a position (about
    // 5 % of the sampler's instructions on the converging lines)
    return AaSignal{{r.rgb[0], r.rgb[1], r.rgb[2]}, {r.normal[0], r.normal[1], r.normal[2]}, r.depth};
}

int zone_count(uint8_t zones) {
    int n = 0;
    for (; zones != 0; zones &= zones - 1) ++n;
    return n;
}

}  // namespace

float aa_contrast(const AaSignal& a, const AaSignal& b) {
    const bool ha = std::isfinite(a.depth), hb = std::isfinite(b.depth);
    if (ha != hb) return 1.0f;
    float c = 0;
    for (int k = 0; k < 3; ++k) c = std::max(c, relative(a.colour[k], b.colour[k]));
    if (ha) {
        c = std::max(c, relative(a.depth, b.depth));
        const float d = a.normal[0] * b.normal[0] + a.normal[1] * b.normal[1] + a.normal[2] * b.normal[2];
        c = std::max(c, 0.5f * (1.0f - std::clamp(d, -1.0f, 1.0f)));
    }
    return std::isfinite(c) ? c : 1.0f;
}

bool aa_sample_is_signal(const RenderScene& scene, const IntegratorSettings& integrator) {
    if (integrator.max_depth != 1 || scene.camera.aperture_radius > 0 || scene.env.present) return false;
    if (scene.lights.size() != 1) return false;
    if (!is_delta_light(scene.lights[0])) return false;
    for (const Material& m : scene.materials)
        if (m.is<Emitter>()) return false;
    return true;
}

AdaptiveSampler::AdaptiveSampler(Film& film, const RenderScene& scene, const RenderKernels& kernels,
                                 const IntegratorSettings& integrator, uint32_t seed, float threshold, AaStats& stats,
                                 const AaEdgeHints* hints)
    : m_film(film),
      m_scene(scene),
      m_kernels(kernels),
      m_seed(seed),
      m_threshold(threshold),
      m_stats(stats),
      m_sample_is_signal(aa_sample_is_signal(scene, integrator)),
      m_hints(hints != nullptr && !hints->empty() ? hints : nullptr) {}

void AdaptiveSampler::begin(const TileRect& tile, int pass) {
    m_tile = tile;
    m_pass = pass;
    m_round = 0;
    const int w = tile.x1 - tile.x0, h = tile.y1 - tile.y0;
    if (w != m_order_w || h != m_order_h) {  // the Morton orders of a tile's size, made once
        m_order_w = w;
        m_order_h = h;
        std::vector<std::pair<uint32_t, int>> order;
        for (int ty = 0; ty < h; ++ty)
            for (int tx = 0; tx < w; ++tx) order.push_back({morton(tx, ty), ty * w + tx});
        std::sort(order.begin(), order.end());
        m_blank_pixels.clear();
        m_row_order.resize(order.size());
        for (const auto& [code, t] : order) {
            PixelState p;
            p.tile_x = t % w;
            p.tile_y = t / w;
            m_row_order[static_cast<size_t>(t)] = static_cast<int>(m_blank_pixels.size());
            m_blank_pixels.push_back(p);
        }
        order.clear();
        for (int cy = 0; cy <= h; ++cy)
            for (int cx = 0; cx <= w; ++cx) order.push_back({morton(cx, cy), cy * (w + 1) + cx});
        std::sort(order.begin(), order.end());
        m_corner_order.clear();
        m_corner_place.clear();
        for (const auto& [code, c] : order) {
            m_corner_order.push_back(c);
            m_corner_place.push_back({c % (w + 1), c / (w + 1)});
        }
    }
    m_pixels = m_blank_pixels;
    for (PixelState& p : m_pixels) p.pixel = (tile.y0 + p.tile_y) * m_film.width() + tile.x0 + p.tile_x;
    m_level2_pixels.clear();
    m_level3_pixels.clear();
    m_level3_first.assign(m_pixels.size(), -1);
    // the pixels a sub-pixel highlight falls on (the pre-pass's pieces, sorted by pixel)
    m_spot_pixels.clear();
    if (m_hints != nullptr && !m_hints->spots.empty()) {
        const std::vector<AaSpot>& spots = m_hints->spots;
        for (size_t i = 0; i < m_pixels.size(); ++i) {
            const auto it = std::lower_bound(spots.begin(), spots.end(), m_pixels[i].pixel,
                                             [](const AaSpot& a, int pixel) { return a.pixel < pixel; });
            if (it == spots.end() || it->pixel != m_pixels[i].pixel) continue;
            m_pixels[i].spot = static_cast<int>(it - spots.begin());
            m_pixels[i].spot_first = kSpotRays * static_cast<int>(m_spot_pixels.size());
            m_spot_pixels.push_back(static_cast<int>(i));
        }
    }
    // a tile's passes run in order (render_job.cpp), so a later pass finds its first pass's
    // decisions; a job continuing another's passes (a distributed render) decides anew
    m_recalled = !m_stats.pattern.empty() && std::all_of(m_pixels.begin(), m_pixels.end(), [&](const PixelState& p) {
        return m_stats.pattern[static_cast<size_t>(p.pixel)] != 0;
    });
}

inline int AdaptiveSampler::corner_of(const PixelState& p, int canonical) const {
    int x = canonical % 2, y = canonical / 2;
    if (p.vertical) {
        const int u = x, v = y;  // (x, y) = (v, 1 - u): 90 degrees counter-clockwise on screen
        x = v;
        y = 1 - u;
    }
    return (p.tile_y + y) * (m_tile.x1 - m_tile.x0 + 1) + p.tile_x + x;
}

inline AaSignal AdaptiveSampler::corner_signal(int corner) const {
    const AaSignalLanes& l = m_corner_lanes;
    const size_t c = static_cast<size_t>(corner);
    return AaSignal{{l.colour[0][c], l.colour[1][c], l.colour[2][c]}, {l.normal[0][c], l.normal[1][c], l.normal[2][c]},
                    l.depth[c]};
}

inline void AdaptiveSampler::place(const PixelState& p, int s, float& fx, float& fy) const {
    const aa::PixelOffset& o = aa::kPixelOffsets[p.vertical ? 1 : 0][s];
    fx = static_cast<float>(m_tile.x0 + p.tile_x + o.x);
    fy = static_cast<float>(m_tile.y0 + p.tile_y + o.y);
}

bool AdaptiveSampler::next_batch(std::vector<CameraSample>& samples) {
    samples.clear();
    const uint32_t pass = static_cast<uint32_t>(m_pass);
    // a pixel's sample s at its fixed position: sample `pass` of the stream of (pixel, s),
    // so that each position's passes are one Sobol sequence
    // (made in place, as the corners below)
    const auto add_sample = [&](int i, int s) {
        CameraSample& sample = samples.emplace_back();
        place(m_pixels[i], s, sample.film_x, sample.film_y);
        sample.key = stream_key(m_seed, static_cast<uint32_t>(m_pixels[i].pixel) * aa::kMaxSamples + s);
        sample.index = pass;
    };
    if (m_round == 0) {
        const uint32_t row = static_cast<uint32_t>(m_film.width()) + 1;
        // written in place, field by field: a sample built and pushed back was a 16-byte load
        // of two 8-byte stores just made, which the core cannot forward (42 % of this
        // function's perf samples on the checkerboard)
        m_corner_count = m_corner_place.size();
        samples.resize(m_corner_count);
        for (size_t q = 0; q < m_corner_count; ++q) {
            const int cx = m_tile.x0 + m_corner_place[q].first, cy = m_tile.y0 + m_corner_place[q].second;
            // keyed by the corner's place in the image: the tiles on both sides of a tile
            // border trace it alike
            const uint32_t id = static_cast<uint32_t>(cy) * row + static_cast<uint32_t>(cx);
            CameraSample& corner = samples[q];
            corner.film_x = static_cast<float>(cx);
            corner.film_y = static_cast<float>(cy);
            corner.key = stream_key(m_seed ^ kCornerSalt, id);
            corner.index = pass;
        }
        // the highlights' grids with the corners: where they fall is known before any ray
        for (const int i : m_spot_pixels) {
            const PixelState& p = m_pixels[i];
            const AaSpot& q = m_hints->spots[static_cast<size_t>(p.spot)];
            const float x0 = static_cast<float>(m_tile.x0 + p.tile_x), y0 = static_cast<float>(m_tile.y0 + p.tile_y);
            for (int k = 0; k < kSpotRays; ++k) {
                const float gx = (static_cast<float>(k % kAaSpotGrid) + 0.5f) / kAaSpotGrid;
                const float gy = (static_cast<float>(k / kAaSpotGrid) + 0.5f) / kAaSpotGrid;
                const uint32_t id = static_cast<uint32_t>(p.pixel) * kSpotRays + static_cast<uint32_t>(k);
                samples.push_back({x0 + q.x0 + gx * (q.x1 - q.x0), y0 + q.y0 + gy * (q.y1 - q.y0),
                                   stream_key(m_seed ^ kSpotSalt, id), pass});
            }
        }
        m_round = 1;
        return !samples.empty();
    }
    // a round of refinement: on to the next round, with a batch when some pixel refines
    // (an empty round falls through to the next)
    const auto refine_round = [&](const std::vector<int>& pixels, const auto& add_pixel_samples) {
        ++m_round;
        for (const int i : pixels) add_pixel_samples(i);
        return !pixels.empty();
    };
    const auto level2_samples = [&](int i) {
        for (int s = aa::kCorners; s < aa::kCorners + aa::kLevel2; ++s) add_sample(i, s);
    };
    const auto zigzag_samples = [&](int i) {  // level 3: a zigzag in each of the pixel's zones
        for (int z = 0; z < aa::kZones; ++z) {
            if (!((m_pixels[i].zones >> z) & 1)) continue;
            for (int k = 0; k < aa::kZigzag; ++k) add_sample(i, aa::kCorners + aa::kLevel2 + z * aa::kZigzag + k);
        }
    };
    if (m_round == 1 && refine_round(m_level2_pixels, level2_samples)) return true;
    if (m_round == 2 && refine_round(m_level3_pixels, zigzag_samples)) return true;
    if (m_round < 4) finish(nullptr);  // no level 3 (with one, take_results finished the item)
    m_round = 4;
    return false;
}

const PathResult* AdaptiveSampler::signal_results(const CameraSample* samples, const PathResult* results, size_t n) {
    if (m_sample_is_signal) return results;
    // the round's positions traced again by the direct-light integrator with one key
    // shared by every position of the image: the same light sample and BRDF sample
    // everywhere, so the radiance (highlights included) is a function of the position
    // only (the integrator's own results are noisy: the decisions never look at them)
    m_signal_samples.assign(samples, samples + n);
    const uint32_t key = path_key(m_seed ^ kSignalSalt, 0, 0);
    for (auto& c : m_signal_samples) {
        c.key = key;
        c.index = 0;
    }
    m_signal_out.resize(n);
    trace_signal(m_signal_samples.data(), n, m_signal_out.data());
    return m_signal_out.data();
}

void AdaptiveSampler::trace_signal(const CameraSample* samples, size_t n, PathResult* out) {
    IntegratorSettings direct;
    direct.max_depth = 1;  // emission and direct light, one light sample and one BRDF sample
    m_kernels.trace_paths(m_scene, direct, samples, n, out, m_signal_scratch);
}

void AdaptiveSampler::take_results(const CameraSample* samples, const PathResult* results, size_t n) {
    if (m_round == 1) {
        const size_t nc = m_corner_count;  // then the highlights' grids, which decide nothing
        m_corners.resize(nc);
        m_spot.assign(results + nc, results + n);
        for (size_t q = 0; q < nc; ++q) m_corners[m_corner_order[q]] = results[q];
        if (m_recalled) {
            recall_pattern();
            return;
        }
        const PathResult* signal = signal_results(samples, results, nc);
        m_corner_lanes.resize(nc);
        for (size_t q = 0; q < nc; ++q) m_corner_lanes.set(static_cast<size_t>(m_corner_order[q]), signal[q]);
        classify_corners();
        return;
    }
    if (m_round == 2) {
        m_level2.assign(results, results + n);
        for (size_t j = 0; j < m_level2_pixels.size(); ++j)
            m_pixels[m_level2_pixels[j]].first = static_cast<int>(aa::kLevel2 * j);
        if (!m_recalled) refine_level2(signal_results(samples, results, n), n);
        for (const int i : m_level2_pixels) {
            if (m_pixels[i].zones == 0) continue;
            m_pixels[i].level = 3;
            m_level3_pixels.push_back(i);
        }
        return;
    }
    if (m_round == 3) {
        int next = 0;
        for (const int i : m_level3_pixels) {
            m_level3_first[i] = next;
            for (int z = 0; z < aa::kZones; ++z)
                if ((m_pixels[i].zones >> z) & 1) next += aa::kZigzag;
        }
        finish(results);  // the zigzags' results read where they are, not copied first
        m_round = 4;
    }
}

void AdaptiveSampler::recall_pattern() {
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        PixelState& p = m_pixels[i];
        const uint16_t code = m_stats.pattern[static_cast<size_t>(p.pixel)];
        p.vertical = (code >> 5) & 1;
        p.zones = code & ((1u << aa::kZones) - 1);
        p.direct = (code >> 8) & 1;
        p.level = p.direct ? 3 : (code >> 6 & 3) >= 2 ? 2 : 1;  // level 3 again once its level-2 results are in
        if (p.direct)
            m_level3_pixels.push_back(static_cast<int>(i));
        else if (p.level == 2)
            m_level2_pixels.push_back(static_cast<int>(i));
    }
}

// inline, defined before its use (as record_pixel): a call a pixel through the shared
// library's PLT otherwise
inline void AdaptiveSampler::queue_refinement(int i) {
    PixelState& p = m_pixels[i];
    if (p.level == 1) return;
    // the pre-pass placed the edges in one run of at most kDirectMaxZones zones: their
    // zigzags at once, without E..H (docs/antialiasing.md, "Level 2 skipped")
    p.direct = aa::one_run(p.hint) && zone_count(p.hint) <= kDirectMaxZones;
    if (!p.direct) {
        m_level2_pixels.push_back(i);
        return;
    }
    p.level = 3;
    p.zones = p.hint;
    m_level3_pixels.push_back(i);
}

void AdaptiveSampler::classify_corners() {
    const int w = m_tile.x1 - m_tile.x0, h = m_tile.y1 - m_tile.y0, row = w + 1;
    // each pair of neighbouring corners compared once, for both pixels that share it:
    // across[cy * w + cx] corners (cx, cy)-(cx + 1, cy), down[cy * row + cx] (cx, cy)-(cx, cy + 1)
    // (a row of the tile at a time, in SIMD lanes: render/antialiasing/signal_lanes.h)
    m_across.resize(static_cast<size_t>(w) * (h + 1));
    m_down.resize(static_cast<size_t>(row) * h);
    for (int cy = 0; cy <= h; ++cy)
        aa_differs_lanes(m_corner_lanes, cy * row, cy * row + 1, w, m_threshold, &m_across[cy * w]);
    for (int cy = 0; cy < h; ++cy)
        aa_differs_lanes(m_corner_lanes, cy * row, (cy + 1) * row, row, m_threshold, &m_down[cy * row]);
    const float* depth = m_corner_lanes.depth.data();
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        PixelState& p = m_pixels[i];
        const int tl = p.tile_y * row + p.tile_x;
        const bool horizontal =
            m_across[p.tile_y * w + p.tile_x] || m_across[(p.tile_y + 1) * w + p.tile_x];  // A-B, C-D
        const bool vertical =
            m_down[p.tile_y * row + p.tile_x] || m_down[p.tile_y * row + p.tile_x + 1];  // A-C, B-D
        uint8_t hint[2] = {0, 0};
        if (m_hints != nullptr) {
            // an edge behind what all four corners see is hidden (a surface covers the pixel)
            const float nearest = m_hints->nearest[p.pixel];
            const bool hidden = depth[tl] < 0.99f * nearest && depth[tl + 1] < 0.99f * nearest &&
                                depth[tl + row] < 0.99f * nearest && depth[tl + row + 1] < 0.99f * nearest;
            if (!hidden) {
                hint[0] = m_hints->zones[0][p.pixel];
                hint[1] = m_hints->zones[1][p.pixel];
            }
        }
        const bool geometric = hint[0] != 0 || hint[1] != 0;
        p.level = horizontal || vertical || geometric ? 2 : 1;
        if (horizontal || vertical)
            p.vertical = vertical && !horizontal;  // ambiguous: horizontal
        else  // an edge seen by the pre-pass alone: the gradient across it, the way it crosses fewer zones
            p.vertical = zone_count(hint[1]) < zone_count(hint[0]);
        p.hint = hint[p.vertical ? 1 : 0];
        queue_refinement(static_cast<int>(i));
    }
}

void AdaptiveSampler::refine_level2(const PathResult* signal, size_t n) {
    m_level2_signal.resize(n);
    for (size_t q = 0; q < n; ++q) m_level2_signal[q] = aa_signal(signal[q]);
    for (const int i : m_level2_pixels) {
        PixelState& p = m_pixels[i];
        const AaSignal* pts[aa::kCorners + aa::kLevel2];
        AaSignal corners[aa::kCorners];
        for (int k = 0; k < aa::kCorners; ++k) {
            corners[k] = corner_signal(corner_of(p, k));
            pts[k] = &corners[k];
        }
        for (int k = 0; k < aa::kLevel2; ++k) pts[aa::kCorners + k] = &m_level2_signal[p.first + k];
        // three fours of comparisons, each a 4-bit mask looked up in its zone table
        uint8_t zones = 0;
        for (int f = 0; f < 3; ++f) {
            int mask = 0;
            for (int l = 0; l < 4; ++l) {
                const aa::Pair pr = aa::kComparisons[f][l];
                mask |= (aa_differs(*pts[pr.p], *pts[pr.q], m_threshold) ? 1 : 0) << l;
            }
            zones |= aa::kZoneTable[f][mask];
        }
        p.zones = zones | p.hint;
        if (zone_count(p.hint) >= kCrowdedMinZones) p.zones &= kCrowdedZones;  // any four zones hold 1 or 3
    }
}

inline bool AdaptiveSampler::in_spot(const PixelState& p, int s) const {
    if (p.spot < 0) return false;
    const AaSpot& q = m_hints->spots[static_cast<size_t>(p.spot)];
    float fx, fy;
    place(p, s, fx, fy);
    fx -= static_cast<float>(m_tile.x0 + p.tile_x);
    fy -= static_cast<float>(m_tile.y0 + p.tile_y);
    return fx >= q.x0 && fx <= q.x1 && fy >= q.y0 && fy <= q.y1;
}

inline void AdaptiveSampler::record_pixel(const PixelState& p, bool stats) {
    if (!m_recalled && !m_stats.pattern.empty())
        m_stats.pattern[p.pixel] = aa_pattern_code(p.level, p.vertical, p.zones, p.direct);
    if (!stats) return;
    m_stats.level[p.pixel] = static_cast<uint8_t>(p.level);
    const int zigzags = p.level == 1 ? 0 : zone_count(p.zones);
    const int rays = p.level == 1 ? 1 : 1 + (p.direct ? 0 : aa::kLevel2) + aa::kZigzag * zigzags;
    m_stats.rays[p.pixel] = static_cast<uint8_t>(rays + (p.spot >= 0 ? kSpotRays : 0));
}

void AdaptiveSampler::finish(const PathResult* level3) {
    const bool record = m_pass == 0;
    // in the image's row order, not the rounds' Morton order: the film's rows are read and
    // written front to back, which the hardware prefetches (each pixel's sum is its own, so
    // the order changes no bit)
    const size_t count = m_row_order.size();
    for (size_t j = 0; j < count; ++j) {
        if (j + kFilmLookahead < count)
            m_film.prefetch(m_pixels[static_cast<size_t>(m_row_order[j + kFilmLookahead])].pixel);
        const size_t i = static_cast<size_t>(m_row_order[j]);
        const PixelState& p = m_pixels[i];
        if (p.level == 1 && p.spot < 0) {
            // the mean of its corners, each weighted here: a corner's weighted copy of 13 doubles
            // (104 bytes against its result's 48) cost more in memory than the multiplies
            FilmSum sum;
            for (int k = 0; k < aa::kCorners; ++k) sum.add(m_corners[corner_of(p, k)], aa::kCornerWeightLevel1);
            m_film.add(p.pixel, sum);
            record_pixel(p, record);
            continue;
        }
        // the pattern's samples of the pixel with their weights: f(s, result, weight)
        const auto each_sample = [&](const auto& f) {
            if (p.level == 1) {
                for (int k = 0; k < aa::kCorners; ++k) f(k, m_corners[corner_of(p, k)], aa::kCornerWeightLevel1);
                return;
            }
            const auto& w = (p.direct ? aa::kDirectWeights : aa::kWeights)[p.zones];
            for (int k = 0; k < aa::kCorners; ++k) f(k, m_corners[corner_of(p, k)], w[k]);
            if (!p.direct)
                for (int k = 0; k < aa::kLevel2; ++k) f(aa::kCorners + k, m_level2[p.first + k], w[aa::kCorners + k]);
            int next = m_level3_first[i];
            for (int z = 0; z < aa::kZones; ++z) {
                if (!((p.zones >> z) & 1)) continue;
                for (int k = 0; k < aa::kZigzag; ++k) {
                    const int s = aa::kCorners + aa::kLevel2 + z * aa::kZigzag + k;
                    f(s, level3[next++], w[s]);
                }
            }
        };
        // a highlight's piece: its grid's rays share the piece's area, the pattern's rays
        // outside it the rest (in proportion to their weights)
        FilmSum sum;
        float spot_scale = 1, grid_weight = 0;
        if (p.spot >= 0) {
            const AaSpot& q = m_hints->spots[static_cast<size_t>(p.spot)];
            const double area = static_cast<double>(q.x1 - q.x0) * static_cast<double>(q.y1 - q.y0);
            double outside = 0;
            each_sample([&](int s, const PathResult&, float w) { outside += in_spot(p, s) ? 0.0 : w; });
            spot_scale = outside > 0 ? static_cast<float>((1 - area) / outside) : 0.0f;
            grid_weight = static_cast<float>((outside > 0 ? area : 1.0) / kSpotRays);
            for (int k = 0; k < kSpotRays; ++k) sum.add(m_spot[p.spot_first + k], grid_weight);
        }
        // (the samples inside the piece left out: the grid stands for them)
        each_sample([&](int s, const PathResult& r, float w) {
            if (!in_spot(p, s) && w * spot_scale != 0) sum.add(r, w * spot_scale);
        });
        m_film.add(p.pixel, sum);  // the pixel's samples in one write
        record_pixel(p, record);
    }
}

}  // namespace patina
