// The adaptive antialiasing's fixed data against its documented construction
// (docs/antialiasing.md): positions, the zone table, the Voronoi weights; and the contrast.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "render/antialiasing/adaptive_pattern.h"
#include "render/antialiasing/adaptive_sampler.h"
#include "render/samplers/rng.h"

namespace aa = patina::aa;

TEST(AdaptivePattern, PositionsAreInsideThePixelAndDistinct) {
    for (int s = 0; s < aa::kMaxSamples; ++s) {
        const aa::Point2 p = aa::sample_point(s);
        EXPECT_GE(p.u, 0.0);
        EXPECT_LE(p.u, 1.0);
        EXPECT_GE(p.v, 0.0);
        EXPECT_LE(p.v, 1.0);
        for (int o = 0; o < s; ++o) {
            const aa::Point2 q = aa::sample_point(o);
            EXPECT_GT(std::hypot(p.u - q.u, p.v - q.v), 0.01) << s << " " << o;
        }
    }
}

TEST(AdaptivePattern, ZigzagPointsAreFourPercentApartAlongTheGradientAcrossTheirZone) {
    for (int z = 0; z < aa::kZones; ++z)
        for (int i = 0; i < aa::kZigzag; ++i) {
            const aa::Point2 p = aa::zigzag_point(z, i);
            // with the zone's boundaries, five equal steps of 4 % across the strip
            EXPECT_NEAR(p.u, z * aa::kZoneWidth + 0.04 * (i + 1), 1e-12);
            if (i > 0) {
                const aa::Point2 q = aa::zigzag_point(z, i - 1);
                EXPECT_NEAR(p.u - q.u, 0.04, 1e-12);  // along the gradient
                EXPECT_NEAR(std::fabs(p.v - q.v), 0.5, 1e-12);  // a zigzag: alternating halves
            }
        }
}

// The zone table from its construction: the b links flag the strips they span; along the
// c chains (corner -> outer point -> inner point) an edge is where the status changes.
TEST(AdaptivePattern, ZoneTableFollowsItsConstruction) {
    for (int m = 0; m < 16; ++m) {
        uint8_t b = 0;
        for (int l = 0; l < 4; ++l) {
            if (!((m >> l) & 1)) continue;
            const aa::Pair pr = aa::kComparisons[0][l];
            if (l < 3) {
                // a link between neighbours on the middle row spans exactly one strip
                const double u0 = aa::sample_point(pr.p).u, u1 = aa::sample_point(pr.q).u;
                b |= 1u << static_cast<int>(std::floor(0.5 * (u0 + u1) / aa::kZoneWidth));
            } else if (m == 8) {
                b |= 1u << 2;  // E-H alone: the centre strip
            }
        }
        EXPECT_EQ(aa::kZoneTable[0][m], b) << m;
        for (int f = 1; f < 3; ++f) {
            // walk each chain from its corner; the strip between two consecutive points is
            // flagged when one differs from the corner and the other does not
            uint8_t c = 0;
            const int chains[2][2] = {{0, 1}, {3, 2}};  // lanes: corner-outer, corner-inner
            for (const auto& ch : chains) {
                bool prev = false;
                double prev_u = aa::sample_point(aa::kComparisons[f][ch[0]].p).u;
                for (const int l : ch) {
                    const bool now = (m >> l) & 1;
                    const double u = aa::sample_point(aa::kComparisons[f][l].q).u;
                    if (now != prev) c |= 1u << static_cast<int>(std::floor(0.5 * (u + prev_u) / aa::kZoneWidth));
                    prev = now;
                    prev_u = u;
                }
            }
            EXPECT_EQ(aa::kZoneTable[f][m], c) << f << " " << m;
        }
    }
    EXPECT_EQ(aa::kZoneTable[0][0] | aa::kZoneTable[1][0] | aa::kZoneTable[2][0], 0);  // all equal: nothing
}

TEST(AdaptivePattern, ComparisonsPairALevelTwoPointWithItsNeighbourOrACornerOnItsSide) {
    for (int f = 1; f < 3; ++f)
        for (int l = 0; l < 4; ++l) {
            const aa::Pair pr = aa::kComparisons[f][l];
            EXPECT_LT(pr.p, aa::kCorners);
            EXPECT_GE(pr.q, aa::kCorners);
            EXPECT_LT(std::fabs(aa::sample_point(pr.p).u - aa::sample_point(pr.q).u), 0.5);
        }
}

// Each sample's share of the pixel by a brute-force count on a 400 x 400 grid: each point
// goes to the nearest sample among the members of its strip, member(s, strip)
template <class Member>
std::vector<double> nearest_sample_areas(const Member& member) {
    constexpr int n = 400;
    std::vector<double> count(aa::kMaxSamples, 0.0);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double u = (i + 0.5) / n, v = (j + 0.5) / n;
            const int strip = static_cast<int>(u / aa::kZoneWidth);
            int best = -1;
            double bd = 1e9;
            for (int s = 0; s < aa::kMaxSamples; ++s) {
                if (!member(s, strip)) continue;
                const aa::Point2 p = aa::sample_point(s);
                const double d = (p.u - u) * (p.u - u) + (p.v - v) * (p.v - v);
                if (d < bd) bd = d, best = s;
            }
            count[best] += 1.0 / (n * n);
        }
    return count;
}

TEST(AdaptivePattern, WeightsAreVoronoiAreasWithinTheStripsSummingToOnePerPattern) {
    for (int z = 0; z < aa::kPatterns; ++z) {
        double sum = 0;
        for (int s = 0; s < aa::kMaxSamples; ++s) {
            const float w = aa::kWeights[z][s];
            EXPECT_GE(w, 0.0f);
            EXPECT_EQ(w > 0, aa::in_pattern(s, z)) << z << " " << s;
            sum += w;
        }
        EXPECT_NEAR(sum, 1.0, 1e-6) << z;
    }
    // against a brute-force count on a fine grid, for a few patterns: each point of the
    // pixel goes to the nearest sample among those of its strip
    for (const int z : {0, 1, 4, 21, 31}) {
        const std::vector<double> count =
            nearest_sample_areas([&](int s, int strip) { return aa::in_pattern(s, z) && aa::in_strip(s, strip); });
        for (int s = 0; s < aa::kMaxSamples; ++s) EXPECT_NEAR(aa::kWeights[z][s], count[s], 3e-3) << z << " " << s;
    }
}

TEST(AdaptivePattern, DirectWeightsAreVoronoiAreasWithinTheStripsWithoutLevelTwo) {
    for (int z = 0; z < aa::kPatterns; ++z) {
        if (!aa::one_run(z)) {
            for (int s = 0; s < aa::kMaxSamples; ++s) EXPECT_EQ(aa::kDirectWeights[z][s], 0.0f) << z;
            continue;
        }
        double sum = 0;
        for (int s = 0; s < aa::kMaxSamples; ++s) {
            const float w = aa::kDirectWeights[z][s];
            const bool level2 = s >= aa::kCorners && s < aa::kCorners + aa::kLevel2;
            EXPECT_EQ(w > 0, aa::in_pattern(s, z) && !level2) << z << " " << s;
            sum += w;
        }
        EXPECT_NEAR(sum, 1.0, 1e-6) << z;
    }
    for (const int z : {1, 2, 6, 14, 24, 31}) {
        const std::vector<double> count = nearest_sample_areas([&](int s, int strip) {
            const bool refined = (z >> strip) & 1, left = (z >> strip) != 0;
            const aa::Point2 p = aa::sample_point(s);
            if (s < aa::kCorners) return refined ? aa::in_strip(s, strip) : left ? p.u == 0 : p.u == 1;
            const bool zigzag = s >= aa::kCorners + aa::kLevel2;
            return refined && zigzag && aa::in_pattern(s, z) && aa::in_strip(s, strip);
        });
        for (int s = 0; s < aa::kMaxSamples; ++s)
            EXPECT_NEAR(aa::kDirectWeights[z][s], count[s], 3e-3) << z << " " << s;
    }
}

TEST(AdaptivePattern, OneRunIsNeighbouringZones) {
    EXPECT_FALSE(aa::one_run(0));
    for (const int z : {1, 2, 4, 8, 16, 3, 6, 12, 24, 7, 14, 28, 15, 30, 31}) EXPECT_TRUE(aa::one_run(z)) << z;
    for (const int z : {5, 9, 17, 10, 11, 13, 19, 21, 27, 29}) EXPECT_FALSE(aa::one_run(z)) << z;
}

TEST(AdaptivePattern, MirrorSymmetricLevelTwoWeights) {
    // E..H mirror about u = 1/2, so without zigzags their weights mirror too
    EXPECT_NEAR(aa::kWeights[0][aa::kE], aa::kWeights[0][aa::kH], 1e-6);
    EXPECT_NEAR(aa::kWeights[0][aa::kF], aa::kWeights[0][aa::kG], 1e-6);
    for (int k = 0; k < aa::kCorners; ++k) EXPECT_NEAR(aa::kWeights[0][k], aa::kWeights[0][0], 1e-6);
}

TEST(AdaptiveContrast, IsScaleFreeAndSeesHitsAndMisses) {
    const float inf = std::numeric_limits<float>::infinity();
    patina::AaSignal a{{1, 1, 1}, {0, 0, 1}, 2}, b{{1.5f, 1, 1}, {0, 0, 1}, 2};
    const float bright = patina::aa_contrast(a, b);
    for (float& c : a.colour) c *= 1e-4f;
    for (float& c : b.colour) c *= 1e-4f;
    EXPECT_NEAR(patina::aa_contrast(a, b), bright, 1e-6);  // the same in the dark
    EXPECT_NEAR(bright, 0.2f, 1e-6);
    patina::AaSignal miss{{1, 1, 1}, {0, 0, 0}, inf};
    EXPECT_EQ(patina::aa_contrast(a, miss), 1.0f);
    EXPECT_EQ(patina::aa_contrast(miss, miss), 0.0f);
    patina::AaSignal turned = a;
    turned.normal[2] = 0;
    turned.normal[0] = 1;
    EXPECT_NEAR(patina::aa_contrast(a, turned), 0.5f, 1e-6);  // 90 degrees
    patina::AaSignal nan = a;
    nan.colour[0] = std::nanf("");
    EXPECT_EQ(patina::aa_contrast(a, nan), 1.0f);
}

// The sampler compares with aa_differs, the contrast test with its divisions multiplied
// out: the same decisions (away from ties) on signals of every kind, misses and NaN included
TEST(AdaptiveContrast, DiffersDecidesAsTheContrastAgainstTheThreshold) {
    uint32_t h = 12345;
    const auto next = [&] {
        h = patina::hash_u32(h);
        return static_cast<float>(h >> 8) / 16777216.0f;
    };
    const float inf = std::numeric_limits<float>::infinity();
    int checked = 0;
    for (int k = 0; k < 20000; ++k) {
        patina::AaSignal s[2];
        for (auto& g : s) {
            for (float& c : g.colour) c = next() < 0.1f ? 0.0f : 10 * next();
            const float nz = next();
            g.normal[0] = std::sqrt(1 - nz * nz);
            g.normal[1] = 0;
            g.normal[2] = nz;
            g.depth = next() < 0.1f ? inf : 1 + next();
        }
        if (k % 97 == 0) s[1].colour[1] = std::nanf("");
        for (const float t : {0.0f, 0.05f, 0.15f, 0.5f, 1.0f}) {
            const float c = patina::aa_contrast(s[0], s[1]);
            if (std::fabs(c - t) < 1e-5f) continue;  // a tie: rounding may go either way
            EXPECT_EQ(patina::aa_differs(s[0], s[1], t), c > t) << k << " " << t;
            ++checked;
        }
    }
    EXPECT_GT(checked, 80000);  // (the ties: contrasts of 0 at threshold 0 and of 1 at 1)
}

// ---- the sampler's rounds on synthetic results and a known signal ---------------------------

#include <functional>
#include <utility>
#include <vector>

#include "render/camera/film.h"

namespace {

struct TileRun {
    patina::Film film{8, 8};
    patina::AaStats stats;
    std::vector<patina::CameraSample> traced;
};

using HitFn = std::function<bool(float, float)>;
using RgbFn = std::function<float(float, float)>;

// hit(fx, fy): the first hit exists there; rgb(fx, fy): its radiance
void fill(const patina::CameraSample* cs, size_t n, patina::PathResult* out, const HitFn& hit, const RgbFn& rgb) {
    for (size_t i = 0; i < n; ++i) {
        patina::PathResult& p = out[i];
        const bool h = hit(cs[i].film_x, cs[i].film_y);
        const float v = rgb(cs[i].film_x, cs[i].film_y);
        for (int k = 0; k < 3; ++k) {
            p.rgb[k] = v;
            p.albedo[k] = h ? 0.5f : 0.0f;
            p.normal[k] = h && k == 2 ? 1.0f : 0.0f;
        }
        p.depth = h ? 3.0f : std::numeric_limits<float>::infinity();
        p.illuminance = 0;
    }
}

// The sampler with a known signal instead of a traced one: `signal_rgb` at each position;
// counts the positions whose signal it was asked for
class KnownSignal final : public patina::AdaptiveSampler {
public:
    KnownSignal(patina::Film& film, const patina::RenderScene& scene, patina::AaStats& stats, HitFn hit,
                RgbFn signal_rgb, const patina::AaEdgeHints* hints)
        : AdaptiveSampler(film, scene, patina::render_kernels_w1(), patina::IntegratorSettings{}, 7,
                          patina::kDefaultAaThreshold, stats, hints),
          m_hit(std::move(hit)),
          m_rgb(std::move(signal_rgb)) {}
    size_t signal_positions = 0;

protected:
    void trace_signal(const patina::CameraSample* samples, size_t n, patina::PathResult* out) override {
        signal_positions += n;
        fill(samples, n, out, m_hit, m_rgb);
    }

private:
    HitFn m_hit;
    RgbFn m_rgb;
};

// one pass of the tile (1, 1)-(7, 6) of an 8 x 8 image; the integrator's radiance is rgb
void run_pass(TileRun& r, KnownSignal& s, int pass, const HitFn& hit, const RgbFn& rgb) {
    s.begin(patina::TileRect{1, 1, 7, 6}, pass);
    std::vector<patina::CameraSample> cs;
    while (s.next_batch(cs)) {
        std::vector<patina::PathResult> out(cs.size());
        fill(cs.data(), cs.size(), out.data(), hit, rgb);
        r.traced.insert(r.traced.end(), cs.begin(), cs.end());
        s.take_results(cs.data(), out.data(), cs.size());
    }
}

patina::RenderScene eight_by_eight() {
    patina::RenderScene scene;
    scene.camera.width = scene.camera.height = 8;
    return scene;
}

// the integrator's radiance is rgb; the signal's is signal_rgb (default: the same)
void run_tile(TileRun& r, const HitFn& hit, const RgbFn& rgb, RgbFn signal_rgb = nullptr,
              const patina::AaEdgeHints* hints = nullptr) {
    const patina::RenderScene scene = eight_by_eight();
    r.stats.level.assign(64, 0);
    r.stats.rays.assign(64, 0);
    KnownSignal s(r.film, scene, r.stats, hit, signal_rgb ? signal_rgb : rgb, hints);
    run_pass(r, s, 0, hit, rgb);
}

std::vector<float> image(const TileRun& r) {
    std::vector<float> rgb(3 * 64), al(3 * 64), n(3 * 64), d(64), lux(64), w(64);
    r.film.resolve(rgb.data(), al.data(), n.data(), d.data(), lux.data(), w.data());
    std::vector<float> out(64);
    for (int i = 0; i < 64; ++i) out[i] = rgb[3 * i];
    return out;
}

float noise(float x, float y) {
    // a deterministic "noisy" radiance: a hash of the position
    const uint32_t h = patina::hash_u32(static_cast<uint32_t>(x * 4096) * 7919u + static_cast<uint32_t>(y * 4096));
    return static_cast<float>(h >> 8) / 16777216.0f;
}

}  // namespace

TEST(AdaptiveSampler, AFlatNoisyRegionStaysAtLevelOneAndIsTheMeanOfItsCorners) {
    TileRun r;
    // the integrator's radiance is noise; the signal (deterministic) is flat
    run_tile(r, [](float, float) { return true; }, noise, [](float, float) { return 0.5f; });
    const std::vector<float> img = image(r);
    for (int y = 1; y < 6; ++y)
        for (int x = 1; x < 7; ++x) {
            EXPECT_EQ(r.stats.level[y * 8 + x], 1);
            const float mean = 0.25f * (noise(x, y) + noise(x + 1, y) + noise(x, y + 1) + noise(x + 1, y + 1));
            EXPECT_NEAR(img[y * 8 + x], mean, 1e-6);
        }
    EXPECT_EQ(r.traced.size(), 7u * 6u);  // the (w + 1) x (h + 1) corners, none twice
    for (size_t i = 0; i < r.traced.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            EXPECT_FALSE(r.traced[i].film_x == r.traced[j].film_x && r.traced[i].film_y == r.traced[j].film_y);
}

TEST(AdaptiveSampler, AVerticalEdgeIsFoundInItsColumnAndItsCoverageEstimated) {
    TileRun r;
    const float edge = 3.3f;  // hit left of x = 3.3
    run_tile(r, [&](float x, float) { return x < edge; }, [&](float x, float) { return x < edge ? 1.0f : 0.0f; });
    const std::vector<float> img = image(r);
    for (int y = 1; y < 6; ++y)
        for (int x = 1; x < 7; ++x) {
            EXPECT_EQ(r.stats.level[y * 8 + x], x == 3 ? 3 : 1) << x << " " << y;
            if (x == 3) {
                EXPECT_EQ(r.stats.rays[y * 8 + x], 9);  // one zigzag: zone 1 (u 0.2-0.4)
                EXPECT_NEAR(img[y * 8 + x], 0.3f, 0.04f);
            } else {
                EXPECT_EQ(img[y * 8 + x], x < 3 ? 1.0f : 0.0f);
            }
        }
}

TEST(AdaptiveSampler, AHorizontalEdgeIsFoundInItsRowThroughTheRotatedPattern) {
    TileRun r;
    const float edge = 2.7f;  // hit above y = 2.7
    run_tile(r, [&](float, float y) { return y < edge; }, [&](float, float y) { return y < edge ? 1.0f : 0.0f; });
    const std::vector<float> img = image(r);
    for (int y = 1; y < 6; ++y)
        for (int x = 1; x < 7; ++x) {
            EXPECT_EQ(r.stats.level[y * 8 + x], y == 2 ? 3 : 1) << x << " " << y;
            if (y == 2) {
                EXPECT_EQ(r.stats.rays[y * 8 + x], 9);
                EXPECT_NEAR(img[y * 8 + x], 0.7f, 0.04f);
            }
        }
    for (const auto& c : r.traced) {  // every sample inside the tile
        EXPECT_GE(c.film_x, 1.0f);
        EXPECT_LE(c.film_x, 7.0f);
        EXPECT_GE(c.film_y, 1.0f);
        EXPECT_LE(c.film_y, 6.0f);
    }
}

// A line thinner than the gaps between the corners and E..H (x in [3.45, 3.55]: between F
// and G of column 3) is invisible to the rays of levels 1 and 2; the geometric pre-pass's
// edges send its pixels to level 3, where the zigzag of zone 2 finds it
TEST(AdaptiveSampler, AThinLineBetweenTheRaysIsFoundThroughTheGeometricPrePass) {
    const auto on = [](float x, float) { return x >= 3.45f && x <= 3.55f ? 1.0f : 0.0f; };
    const auto hit = [](float, float) { return true; };
    patina::AaEdgeHints hints;
    hints.resize(8, 8);
    std::vector<double> crossings;  // rasterise_edge's scratch
    for (const float x : {3.45f, 3.55f})
        patina::rasterise_edge(hints, x, 0.0f, x, 8.0f, 2.0f, 2.0f, 0.5f, 0.5f, crossings);
    TileRun blind, seen;
    run_tile(blind, hit, on);
    run_tile(seen, hit, on, nullptr, &hints);
    const std::vector<float> a = image(blind), b = image(seen);
    for (int y = 1; y < 6; ++y) {
        const int i = y * 8 + 3;
        EXPECT_EQ(blind.stats.level[i], 1);
        EXPECT_EQ(a[i], 0.0f);
        EXPECT_EQ(seen.stats.level[i], 3);
        // one zigzag, level 2 skipped: both sides of the line are in zone 2, which the
        // pre-pass says
        EXPECT_EQ(seen.stats.rays[i], 5);
        // the line's share is the weights of the zigzag's rays on it (u = 0.48 and 0.52)
        const auto& w = aa::kDirectWeights[1 << 2];
        const int first = aa::kCorners + aa::kLevel2 + 2 * aa::kZigzag;
        EXPECT_NEAR(b[i], w[first + 1] + w[first + 2], 1e-6);
        EXPECT_NEAR(b[i], 0.1f, 0.1f);  // coverage 0.1, to the zigzag's resolution
        EXPECT_EQ(seen.stats.level[i + 1], 1);  // its neighbours stay at level 1
    }
    // an edge behind what all four corners see (depth 3 here) is hidden: no refinement
    for (auto& d : hints.nearest)
        if (std::isfinite(d)) d = 10.0f;
    TileRun hidden;
    run_tile(hidden, hit, on, nullptr, &hints);
    for (int y = 1; y < 6; ++y) EXPECT_EQ(hidden.stats.level[y * 8 + 3], 1);
}

// A highlight far smaller than the gaps between the rays (a Gaussian spot of sigma 0.02
// pixel, 1000 times the background) falls between them: the pattern misses it. The
// pre-pass's piece around it gets a grid of 8 x 8 rays, which weighs in with the piece's
// area and the pattern's rays outside it with the rest: the pixel is the spot's integral.
TEST(AdaptiveSampler, ASubPixelHighlightIsIntegratedByItsPiecesGrid) {
    constexpr float cx = 3.37f, cy = 2.61f, sigma = 0.02f, peak = 1000.0f;
    const auto spot = [&](float x, float y) {
        const float r2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
        return 1.0f + peak * std::exp(-0.5f * r2 / (sigma * sigma));
    };
    const auto hit = [](float, float) { return true; };
    TileRun blind;
    run_tile(blind, hit, spot);
    const int i = 2 * 8 + 3;
    EXPECT_NEAR(image(blind)[i], 1.0f, 1e-3);  // missed
    patina::AaEdgeHints hints;
    hints.resize(8, 8);
    const float half = 5 * sigma;  // the piece: the spot's centre +- 5 sigma
    hints.spots.push_back({i, cx - 3 - half, cy - 2 - half, cx - 3 + half, cy - 2 + half});
    TileRun seen;
    run_tile(seen, hit, spot, nullptr, &hints);
    const std::vector<float> img = image(seen);
    const double integral = 1.0 + peak * 2 * 3.14159265358979 * sigma * sigma;  // the pixel's mean
    EXPECT_NEAR(img[i], integral, 0.01 * integral);
    EXPECT_EQ(seen.stats.level[i], 1);  // the pattern is what it was
    EXPECT_EQ(seen.stats.rays[i], 1 + patina::kAaSpotGrid * patina::kAaSpotGrid);
    int grid = 0;  // the grid's rays inside the piece, traced with the corners
    for (const auto& c : seen.traced) grid += std::fabs(c.film_x - cx) < half && std::fabs(c.film_y - cy) < half;
    EXPECT_EQ(grid, patina::kAaSpotGrid * patina::kAaSpotGrid);
    EXPECT_EQ(seen.traced.size(), blind.traced.size() + grid);
    const std::vector<float> without = image(blind);
    for (int k = 0; k < 64; ++k) {
        if (k != i) {
            EXPECT_EQ(img[k], without[k]) << k;  // the other pixels are untouched
        }
    }
    // a piece over a corner of the pattern leaves that corner out: the pixel is the rest
    // of the pattern and the grid, each by its area, and the grid's weights are finite
    patina::AaEdgeHints corner;
    corner.resize(8, 8);
    corner.spots.push_back({i, 0.0f, 0.0f, 0.1f, 0.1f});
    TileRun c;
    run_tile(c, hit, [](float x, float y) { return x == 3.0f && y == 2.0f ? 1e6f : 1.0f; }, nullptr, &corner);
    EXPECT_NEAR(image(c)[i], 1.0f, 1e-5);
}

namespace {

// the oblique edge x + 0.3 y = 3.3 rendered in two passes that keep the first pass's
// decisions and in two that decide anew: the same positions, keys and sums
void check_later_pass(const patina::AaEdgeHints* hints) {
    const float edge = 3.3f;
    const HitFn hit = [&](float x, float y) { return x + 0.3f * y < edge; };
    const RgbFn rgb = [&](float x, float y) { return (x + 0.3f * y < edge ? 1.0f : 0.0f) + 0.1f * noise(x, y); };
    const RgbFn signal = [&](float x, float y) { return x + 0.3f * y < edge ? 1.0f : 0.0f; };
    const patina::RenderScene scene = eight_by_eight();
    TileRun kept, anew;
    for (TileRun* r : {&kept, &anew}) {
        r->stats.level.assign(64, 0);
        r->stats.rays.assign(64, 0);
    }
    kept.stats.pattern.assign(64, 0);  // anew: no pattern kept, every pass decides
    KnownSignal keeps(kept.film, scene, kept.stats, hit, signal, hints);
    KnownSignal decides(anew.film, scene, anew.stats, hit, signal, hints);
    run_pass(kept, keeps, 0, hit, rgb);
    run_pass(anew, decides, 0, hit, rgb);
    const size_t first_pass_signal = keeps.signal_positions;
    EXPECT_EQ(first_pass_signal, decides.signal_positions);
    EXPECT_GT(first_pass_signal, 0u);
    kept.traced.clear();
    anew.traced.clear();
    run_pass(kept, keeps, 1, hit, rgb);
    run_pass(anew, decides, 1, hit, rgb);
    EXPECT_EQ(keeps.signal_positions, first_pass_signal);  // none in pass 1
    ASSERT_EQ(kept.traced.size(), anew.traced.size());
    for (size_t i = 0; i < kept.traced.size(); ++i) {
        EXPECT_EQ(kept.traced[i].film_x, anew.traced[i].film_x);
        EXPECT_EQ(kept.traced[i].film_y, anew.traced[i].film_y);
        EXPECT_EQ(kept.traced[i].key, anew.traced[i].key);
        EXPECT_EQ(kept.traced[i].index, anew.traced[i].index);
    }
    EXPECT_EQ(image(kept), image(anew));
    EXPECT_EQ(kept.stats.level, anew.stats.level);
    int refined = 0;
    for (int i = 0; i < 64; ++i) refined += kept.stats.level[i] == 3;
    EXPECT_GT(refined, 0);  // the oblique edge was refined: the kept decisions are not all level 1
}

}  // namespace

// An edge that the corners see and the pre-pass places (x = 3.3: zone 1 of column 3) is
// refined without level 2: the zigzag of zone 1 alone, no ray on the middle row, and its
// coverage estimated as with level 2
TEST(AdaptiveSampler, AnEdgeThePrePassPlacesSkipsLevelTwo) {
    const float edge = 3.3f;
    const HitFn hit = [&](float x, float) { return x < edge; };
    const RgbFn rgb = [&](float x, float) { return x < edge ? 1.0f : 0.0f; };
    patina::AaEdgeHints hints;
    hints.resize(8, 8);
    std::vector<double> crossings;  // rasterise_edge's scratch
    patina::rasterise_edge(hints, edge, 0.0f, edge, 8.0f, 2.0f, 2.0f, 0.5f, 0.5f, crossings);
    TileRun r;
    run_tile(r, hit, rgb, nullptr, &hints);
    const std::vector<float> img = image(r);
    for (int y = 1; y < 6; ++y) {
        const int i = y * 8 + 3;
        EXPECT_EQ(r.stats.level[i], 3);
        EXPECT_EQ(r.stats.rays[i], 5);
        EXPECT_NEAR(img[i], 0.3f, 0.04f);
        EXPECT_EQ(r.stats.level[i - 1], 1);
        EXPECT_EQ(r.stats.level[i + 1], 1);
    }
    for (const auto& c : r.traced) EXPECT_NE(c.film_y, std::floor(c.film_y) + 0.5f) << c.film_x;  // no E..H
}

// A pixel crossed by edges in four zones (crowded: several edges) traces level 2 as before
// (its middle row tells the strips apart), then the zigzags of zones 1 and 3 only, and its
// value is still the coverage of the stripes finer than a fifth of the pixel (half)
TEST(AdaptiveSampler, APixelCrowdedWithEdgesTracesLevelTwoAndTwoZigzags) {
    const auto on = [](float x, float) { return std::fmod(x, 0.2f) < 0.1f ? 1.0f : 0.0f; };
    const auto hit = [](float, float) { return true; };
    patina::AaEdgeHints hints;
    hints.resize(8, 8);
    std::vector<double> crossings;  // rasterise_edge's scratch
    for (const float x : {3.1f, 3.3f, 3.5f, 3.7f})
        patina::rasterise_edge(hints, x, 0.0f, x, 8.0f, 2.0f, 2.0f, 0.5f, 0.5f, crossings);
    TileRun r;
    run_tile(r, hit, on, nullptr, &hints);
    const std::vector<float> img = image(r);
    for (int y = 1; y < 6; ++y) {
        EXPECT_EQ(r.stats.level[y * 8 + 3], 3);
        EXPECT_EQ(r.stats.rays[y * 8 + 3], 1 + aa::kLevel2 + 2 * aa::kZigzag);
        EXPECT_NEAR(img[y * 8 + 3], 0.5f, 0.1f) << y;
    }
    for (const auto& c : r.traced) {
        const float u = c.film_x - std::floor(c.film_x), v = c.film_y - std::floor(c.film_y);
        if (c.film_x < 3 || c.film_x >= 4 || (v != 0.25f && v != 0.75f)) continue;
        EXPECT_TRUE((u > 0.2f && u < 0.4f) || (u > 0.6f && u < 0.8f)) << u;  // zones 1 and 3
    }
}

// The decisions are the same in every pass, so a later pass keeps the first's: it traces
// the same positions with the same keys as a pass that decides anew, gives the same sums,
// and asks for no signal; with the pre-pass's hints (level 2 skipped) too
TEST(AdaptiveSampler, ALaterPassKeepsTheFirstPassDecisionsAndTracesNoSignal) {
    patina::AaEdgeHints hints;
    hints.resize(8, 8);
    std::vector<double> crossings;  // rasterise_edge's scratch
    patina::rasterise_edge(hints, 3.3f, 0.0f, 3.3f - 0.3f * 8, 8.0f, 2.0f, 2.0f, 0.5f, 0.5f, crossings);
    check_later_pass(nullptr);
    check_later_pass(&hints);
}

// A level-1 pixel adds its corners' terms, each weighted once for the four pixels sharing it:
// the same bits as weighting the four corners in the pixel, hits and misses (no depth) alike
TEST(AdaptiveSampler, ALevelOnePixelIsItsCornersWeightedInThePixelBitForBit) {
    for (const bool hits : {true, false}) {
        TileRun r;
        const HitFn hit = [&](float, float) { return hits; };
        run_tile(r, hit, noise, [](float, float) { return 0.5f; });
        patina::Film expected(8, 8);
        for (int y = 1; y < 6; ++y)
            for (int x = 1; x < 7; ++x) {
                ASSERT_EQ(r.stats.level[y * 8 + x], 1);
                const float cx[4] = {0, 1, 0, 1}, cy[4] = {0, 0, 1, 1};  // A, B, C, D
                for (int k = 0; k < 4; ++k) {
                    const patina::CameraSample c{static_cast<float>(x) + cx[k], static_cast<float>(y) + cy[k], 0, 0};
                    patina::PathResult corner;
                    fill(&c, 1, &corner, hit, noise);
                    expected.add(y * 8 + x, corner, 0.25f);
                }
            }
        std::vector<float> w(64), rgb(192), al(192), n(192), d(64), lux(64);
        std::vector<float> rgb2(192), al2(192), n2(192), d2(64), lux2(64), w2(64);
        r.film.resolve(rgb.data(), al.data(), n.data(), d.data(), lux.data(), w.data());
        expected.resolve(rgb2.data(), al2.data(), n2.data(), d2.data(), lux2.data(), w2.data());
        for (int y = 1; y < 6; ++y)
            for (int x = 1; x < 7; ++x) {
                const int i = y * 8 + x;
                for (int k = 0; k < 3; ++k) {
                    EXPECT_EQ(rgb[3 * i + k], rgb2[3 * i + k]);
                    EXPECT_EQ(al[3 * i + k], al2[3 * i + k]);
                    EXPECT_EQ(n[3 * i + k], n2[3 * i + k]);
                }
                if (hits)
                    EXPECT_EQ(d[i], d2[i]);
                else  // no depth: whatever resolve gives a pixel without one, both alike
                    EXPECT_EQ(std::isfinite(d[i]), std::isfinite(d2[i]));
                EXPECT_EQ(w[i], w2[i]);
            }
    }
}
