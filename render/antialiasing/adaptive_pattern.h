// The fixed geometry of the adaptive antialiasing (thesis chapter 3; docs/antialiasing.md):
// where every sample of a pixel lies, which pairs are compared, the zone table, and each
// sample's filter weight for every refinement pattern. All of it is constexpr data built
// here from its documented construction, so the tests can check the construction and the
// sampler never computes a weight at render time.
//
// Canonical frame: (u, v) in the unit pixel, u to the right, v down, the presumed gradient
// along u (a "horizontal" discontinuity: high contrast A-B or C-D). A pixel whose
// discontinuity is vertical uses the same frame rotated 90 degrees counter-clockwise on
// screen: pixel (x, y) = (v, 1 - u). The square maps onto itself and distances are kept,
// so the weights are the same in both orientations.
#pragma once

#include <array>
#include <cstdint>
#include <utility>

namespace patina::aa {

struct Point2 {
    double u, v;
};

// Sample indices within a pixel's pattern: 0-3 the corners A, B, C, D (level 1, shared
// with the neighbours), 4-7 E, F, G, H (level 2), 8 + 4 j + i the i-th point of zone j's
// zigzag (level 3).
inline constexpr int kCorners = 4, kLevel2 = 4, kZones = 5, kZigzag = 4;
inline constexpr int kMaxSamples = kCorners + kLevel2 + kZones * kZigzag;  // 28
inline constexpr int kPatterns = 1 << kZones;                               // zone subsets
inline constexpr int kA = 0, kB = 1, kC = 2, kD = 3, kE = 4, kF = 5, kG = 6, kH = 7;

// Level 2: four points on the middle row at the zone boundaries u = 0.2, 0.4, 0.6, 0.8.
// Zone j is the strip u in [0.2 j, 0.2 (j + 1)] (the whole height of the pixel): the five
// intervals along the gradient that the row and the corners bracket.
inline constexpr double kZoneWidth = 1.0 / kZones;
inline constexpr double kZigzagStep = 0.04;  // the thesis: 4 % of the pixel side along the gradient

// A zigzag crosses its strip along the gradient: u steps by kZigzagStep from the strip's
// left boundary, u = 0.2 j + 0.04 (i + 1), so with the level-2 points on the boundaries the
// strip is cut into five equal steps and the edge is placed to 4 % of the pixel; v
// alternates between the upper and the lower half (1/4, 3/4), so the four rays sample the
// edge at two heights.
constexpr Point2 zigzag_point(int zone, int i) {
    return {zone * kZoneWidth + (i + 1) * kZigzagStep, i % 2 == 0 ? 0.25 : 0.75};
}

constexpr Point2 sample_point(int s) {
    if (s < kCorners) return {static_cast<double>(s % 2), static_cast<double>(s / 2)};
    if (s < kCorners + kLevel2) return {(s - kCorners + 1) * kZoneWidth, 0.5};
    const int z = (s - kCorners - kLevel2) / kZigzag, i = (s - kCorners - kLevel2) % kZigzag;
    return zigzag_point(z, i);
}

// Every sample's place in the pixel for each orientation, [vertical][s]: (x, y) on screen,
// the canonical (u, v) as it is (0) or turned 90 degrees counter-clockwise, (v, 1 - u) (1).
// A table, not sample_point's divisions at each of a round's rays.
struct PixelOffset {
    double x, y;
};
inline constexpr std::array<std::array<PixelOffset, kMaxSamples>, 2> kPixelOffsets = [] {
    std::array<std::array<PixelOffset, kMaxSamples>, 2> table{};
    for (int s = 0; s < kMaxSamples; ++s) {
        const Point2 q = sample_point(s);
        table[0][s] = {q.u, q.v};
        table[1][s] = {q.v, 1.0 - q.u};
    }
    return table;
}();

// The three fours of comparisons, lanes 0-3 each (one 4-wide compare each):
//   b:  E-F, F-G, G-H along the middle row, and E-H (a ramp too gentle for any one link)
//   c0: A-E, A-F, B-G, B-H: the top corners against the middle row, each from its own side
//   c1: C-E, C-F, D-G, D-H: the same for the bottom corners
struct Pair {
    int p, q;
};
inline constexpr std::array<std::array<Pair, 4>, 3> kComparisons{{
    {{{kE, kF}, {kF, kG}, {kG, kH}, {kE, kH}}},
    {{{kA, kE}, {kA, kF}, {kB, kG}, {kB, kH}}},
    {{{kC, kE}, {kC, kF}, {kD, kG}, {kD, kH}}},
}};

// Zone flags (bit j = zone j) for a 4-bit mask of failed comparisons (bit l = lane l).
// b: each link flags the strip it spans; E-H failing while no link does (a ramp too
// gentle for any one link) flags only the centre strip, one zigzag. c0/c1: the lanes are two
// chains walked from a corner towards the middle, A -> E -> F and B -> H -> G (the bottom corners C, D alike): along a chain, a lane says
// whether that point differs from the corner, and the edge lies where that status changes
// (corner -> first point: the outer strip, first -> second point: the next strip in).
constexpr uint8_t zone_flags_b(int mask) {
    uint8_t z = 0;
    if (mask & 1) z |= 1u << 1;
    if (mask & 2) z |= 1u << 2;
    if (mask & 4) z |= 1u << 3;
    if (mask == 8) z |= 1u << 2;  // E-H alone: a ramp no link sees (with a link failing, that link says where)
    return z;
}

constexpr uint8_t zone_flags_c(int mask) {
    const bool e = mask & 1, f = mask & 2, g = mask & 4, h = mask & 8;  // differs from its corner
    uint8_t z = 0;
    if (e) z |= 1u << 0;       // A | E: strip 0
    if (e != f) z |= 1u << 1;  // E | F: strip 1
    if (h) z |= 1u << 4;       // B | H: strip 4
    if (h != g) z |= 1u << 3;  // H | G: strip 3
    return z;
}

template <class F>
constexpr std::array<uint8_t, 16> make_zone_table(F flags) {
    std::array<uint8_t, 16> t{};
    for (int m = 0; m < 16; ++m) t[m] = flags(m);
    return t;
}

// One table per four of comparisons, indexed by its mask: the zones to refine are the OR
// of the three lookups.
inline constexpr std::array<std::array<uint8_t, 16>, 3> kZoneTable{
    make_zone_table(zone_flags_b), make_zone_table(zone_flags_c), make_zone_table(zone_flags_c)};

// ---- weights -------------------------------------------------------------------------------
// The pixel is reconstructed strip by strip along the presumed gradient: each zone's strip
// (u in [0.2 j, 0.2 (j + 1)], a fifth of the pixel) is shared by the samples that belong
// to it, those on the strip or on its sides (its zigzag, the level-2 points on its
// boundaries, the corners for the outer strips), and a sample's weight in a strip is the
// area of its Voronoi cell among them, clipped to the strip (a nearest-sample
// reconstruction under the box filter, kept inside the strip). A sample's weight is the sum
// over the strips it belongs to. So a zigzag's rays estimate only their own strip, where the
// edge was found, and do not also stand for the neighbouring strips as a Voronoi cell over
// the whole pixel would (a zigzag 0.12 wide had cells 0.38 of the pixel). Every strip has
// samples on its sides, so a pattern's weights sum to 1.
// Four corners alone (level 1) are not split in strips: 1/4 each, the mean of the corners.

struct Polygon {
    std::array<Point2, 2 * kMaxSamples + 8> p{};
    int n = 0;
};

// Keeps the part of `poly` nearer to `a` than to `b` (Sutherland-Hodgman, one half plane).
constexpr Polygon clip_nearer(const Polygon& poly, Point2 a, Point2 b) {
    const double nx = b.u - a.u, ny = b.v - a.v;
    const double c = 0.5 * (nx * (a.u + b.u) + ny * (a.v + b.v));
    Polygon out;
    for (int i = 0; i < poly.n; ++i) {
        const Point2 s = poly.p[i], e = poly.p[(i + 1) % poly.n];
        const double ds = nx * s.u + ny * s.v - c, de = nx * e.u + ny * e.v - c;  // <= 0: inside
        if (ds <= 0) out.p[out.n++] = s;
        if ((ds < 0 && de > 0) || (ds > 0 && de < 0)) {
            const double t = ds / (ds - de);
            out.p[out.n++] = {s.u + t * (e.u - s.u), s.v + t * (e.v - s.v)};
        }
    }
    return out;
}

constexpr double area(const Polygon& poly) {
    double a = 0;
    for (int i = 0; i < poly.n; ++i) {
        const Point2 s = poly.p[i], e = poly.p[(i + 1) % poly.n];
        a += s.u * e.v - e.u * s.v;
    }
    return 0.5 * (a < 0 ? -a : a);
}

// Is sample s part of the pattern of refined zones `zones` (level 2 reached)?
constexpr bool in_pattern(int s, int zones) {
    return s < kCorners + kLevel2 || ((zones >> ((s - kCorners - kLevel2) / kZigzag)) & 1);
}

// Does sample s belong to strip j: on it or on one of its sides (u in [0.2 j, 0.2 (j + 1)])?
constexpr bool in_strip(int s, int j) {
    const double u = sample_point(s).u, lo = j * kZoneWidth, hi = (j + 1) * kZoneWidth;
    return u >= lo - 1e-9 && u <= hi + 1e-9;
}

// Do `zones` form one run of neighbouring zones (and at least one)?
constexpr bool one_run(int zones) {
    if (zones == 0) return false;
    const int low = zones & -zones;  // the lowest zone's bit
    return ((zones + low) & zones) == 0;
}

// Without level 2 (a pixel whose edges the geometric pre-pass placed in one run of
// neighbouring zones, render/antialiasing/edge_hints.h: it skips E..H and traces only the
// run's zigzags, the pre-pass having said where the edges cross, which is what level 2 is
// for), the strips are shared thus: a refined strip by its zigzag (and the corners on its
// sides, for the outer strips), a strip left of the run by the corners A, C and one right of
// it by B, D (every edge lies in the run, so those strips are on the corners' side).
constexpr bool in_direct_strip(int s, int zones, int j) {
    if (s >= kCorners && s < kCorners + kLevel2) return false;  // no level 2
    if (s >= kCorners + kLevel2) return in_pattern(s, zones) && in_strip(s, j);
    if ((zones >> j) & 1) return in_strip(s, j);  // a refined strip: the corners on its sides
    const bool left = (zones >> j) != 0;          // a refined zone lies right of strip j
    return left ? s % 2 == 0 : s % 2 == 1;        // A, C or B, D
}

// The sample's share of strip j: its Voronoi cell among the strip's samples (`Direct`: the
// pattern without level 2), clipped to the strip.
template <bool Direct>
constexpr double strip_weight(int s, int zones, int j) {
    const auto member = [&](int o) { return Direct ? in_direct_strip(o, zones, j) : in_pattern(o, zones) && in_strip(o, j); };
    if (!member(s)) return 0;
    Polygon cell;
    cell.p[0] = {j * kZoneWidth, 0};
    cell.p[1] = {(j + 1) * kZoneWidth, 0};
    cell.p[2] = {(j + 1) * kZoneWidth, 1};
    cell.p[3] = {j * kZoneWidth, 1};
    cell.n = 4;
    for (int o = 0; o < kMaxSamples; ++o)
        if (o != s && member(o)) cell = clip_nearer(cell, sample_point(s), sample_point(o));
    return area(cell);
}

template <int Zones, bool Direct>
constexpr std::array<float, kMaxSamples> pattern_weights() {
    std::array<float, kMaxSamples> w{};
    if (Direct && !one_run(Zones)) return w;  // never used: such a pixel traces level 2
    for (int s = 0; s < kMaxSamples; ++s) {
        double sum = 0;
        for (int j = 0; j < kZones; ++j) sum += strip_weight<Direct>(s, Zones, j);
        w[s] = static_cast<float>(sum);
    }
    return w;
}

// Each pattern's weights are a constant expression of their own (one evaluation per
// pattern keeps every evaluation well inside the compilers' constexpr step limits).
template <bool Direct, int... Z>
constexpr std::array<std::array<float, kMaxSamples>, kPatterns> make_weights(std::integer_sequence<int, Z...>) {
    return {pattern_weights<Z, Direct>()...};
}

// kWeights[zones][s]: the weight of sample s when level 2 was traced and `zones` refined
// (zones = 0: level 2 found nothing to refine; its eight samples share the pixel).
inline constexpr std::array<std::array<float, kMaxSamples>, kPatterns> kWeights =
    make_weights<false>(std::make_integer_sequence<int, kPatterns>{});

// kDirectWeights[zones][s]: the same when level 2 was skipped and the run `zones` refined
// (E..H weigh 0; all zero where `zones` is not one run). Each pattern's weights sum to 1.
inline constexpr std::array<std::array<float, kMaxSamples>, kPatterns> kDirectWeights =
    make_weights<true>(std::make_integer_sequence<int, kPatterns>{});

inline constexpr float kCornerWeightLevel1 = 0.25f;  // no discontinuity: the mean of the corners

}  // namespace patina::aa
