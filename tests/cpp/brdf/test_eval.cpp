// The tabulated-BRDF evaluator: widths 4 and 8 against width 1, width 1 against a
// plain double-precision reference, batches of any length, threads, symmetries.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "brdf/kernels.h"
#include "brdf/table.h"
#include "core/constants.h"
#include "core/cpu.h"

using namespace patina;

namespace {

std::vector<float> irregular_axis(int n, double lo, double hi, double power) {
    std::vector<float> k(n);
    for (int i = 0; i < n; ++i) k[i] = float(lo + (hi - lo) * std::pow(double(i) / (n - 1), power));
    return k;
}

// A smooth, positive function of the grid coordinates, different per channel. Like a
// real BRDF, it stops depending on an azimuth where that azimuth is undefined (phi_d as
// theta_d -> 0, phi_i as theta_i -> 0), so ill-conditioned angles do not matter.
double smooth(Parametrization p, const double* c, int channel) {
    const int dims = axis_count(p);
    double v = 0.3 + 0.1 * channel;
    for (int a = 0; a < dims; ++a) {
        double term = (0.2 + 0.05 * a) * std::cos(c[a] * (1.0 + 0.3 * a + 0.1 * channel));
        // Azimuths are periodic (halfdiff phi_d with period pi by reciprocity), so the table
        // agrees with itself across the seams, as a measured table does.
        if (p == Parametrization::HalfDiff && a == 2) term = 0.3 * std::cos(2 * c[2] + 0.2 * channel) * std::sin(c[1]);
        if (p == Parametrization::Isotropic && a == 2) term *= std::sin(c[0]) * std::sin(c[1]);
        if (p == Parametrization::Anisotropic && (a == 1 || a == 3))
            term = 0.25 * std::cos(c[a] + 0.3 * channel) * std::sin(c[a - 1]);
        v += term;
    }
    return v * v;
}

Table make_table(Parametrization p, int channels, uint32_t symmetry, bool with_holes) {
    Table t;
    t.parametrization = p;
    t.channels = channels;
    t.channel_kind = channels == 3 ? ChannelKind::RGB : (channels == 1 ? ChannelKind::Mono : ChannelKind::Spectral);
    if (t.channel_kind == ChannelKind::Spectral)
        for (int c = 0; c < channels; ++c) t.wavelengths.push_back(400.0f + 10.0f * c);
    t.symmetry = symmetry;
    switch (p) {
        case Parametrization::Isotropic:
            t.axes = {irregular_axis(17, 0, kPiDouble / 2, 1.3), irregular_axis(19, 0, kPiDouble / 2, 0.8), irregular_axis(23, 0, kPiDouble, 1.5)};
            break;
        case Parametrization::HalfDiff:
            t.axes = {irregular_axis(25, 0, kPiDouble / 2, 2.0), irregular_axis(15, 0, kPiDouble / 2, 1.0),
                      irregular_axis(31, 0, (symmetry & kSymPhiMirror) ? kPiDouble / 2 : kPiDouble, 1.0)};
            break;
        case Parametrization::Anisotropic:
            t.axes = {irregular_axis(9, 0, kPiDouble / 2, 1.2), irregular_axis(13, 0, 2 * kPiDouble, 1.0), irregular_axis(11, 0, kPiDouble / 2, 0.9),
                      irregular_axis(14, 0, 2 * kPiDouble, 1.1)};
            break;
    }
    const int dims = axis_count(p);
    size_t points = 1;
    for (auto& a : t.axes) points *= a.size();
    t.values.resize(points * channels);
    if (with_holes) t.valid.assign(points, 1);
    std::mt19937 rng(77);
    for (size_t i = 0; i < points; ++i) {
        double c[4];
        size_t rest = i;
        for (int a = dims - 1; a >= 0; --a) {
            c[a] = t.axes[a][rest % t.axes[a].size()];
            rest /= t.axes[a].size();
        }
        // no holes on the azimuth seam knots (first and last phi), which must agree
        const size_t last = i % t.axes[dims - 1].size();
        const bool hole = with_holes && (rng() % 50 == 0) && last != 0 && last + 1 != t.axes[dims - 1].size();
        if (hole) t.valid[i] = 0;
        for (int ch = 0; ch < channels; ++ch) t.values[i * channels + ch] = hole ? 0.0f : float(smooth(p, c, ch));
    }
    t.check();
    return t;
}

// ---- the double-precision reference: plain formulas, linear search, no SIMD ----
void ref_coords(const TableView& t, const double* wi, const double* wo, double* c) {
    auto acos_c = [](double x) { return std::acos(std::clamp(x, -1.0, 1.0)); };
    if (t.parametrization == Parametrization::HalfDiff) {
        double h[3] = {wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]};
        const double len = std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
        for (double& x : h) x /= len;
        const double th = acos_c(h[2]), ph = std::atan2(h[1], h[0]);
        // rotate wi by -phi_h about z, then by -theta_h about y
        const double cx = std::cos(-ph), sx = std::sin(-ph);
        const double t0 = cx * wi[0] - sx * wi[1], t1 = sx * wi[0] + cx * wi[1], t2 = wi[2];
        const double cy = std::cos(-th), sy = std::sin(-th);
        const double d0 = cy * t0 + sy * t2, d1 = t1, d2 = -sy * t0 + cy * t2;
        double pd = std::atan2(d1, d0);
        if ((t.symmetry & kSymReciprocity) && pd < 0) pd += kPiDouble;
        if (t.symmetry & kSymPhiMirror) {
            pd = std::fabs(pd);
            if (pd > kPiDouble / 2) pd = kPiDouble - pd;
        }
        c[0] = th;
        c[1] = acos_c(d2);
        c[2] = pd;
    } else if (t.parametrization == Parametrization::Isotropic) {
        double ti = acos_c(wi[2]), to = acos_c(wo[2]);
        if ((t.symmetry & kSymReciprocity) && ti > to) std::swap(ti, to);
        // phi_d = |phi_o - phi_i| folded into [0, pi]; 0 when either direction is on the pole
        const double cross = wi[0] * wo[1] - wi[1] * wo[0], dot = wi[0] * wo[0] + wi[1] * wo[1];
        const double pd = std::atan2(std::fabs(cross), dot);
        c[0] = ti;
        c[1] = to;
        c[2] = pd;
    } else {
        double ti = acos_c(wi[2]), to = acos_c(wo[2]);
        double pi = std::atan2(wi[1], wi[0]), po = std::atan2(wo[1], wo[0]);
        if (pi < 0) pi += 2 * kPiDouble;
        if (po < 0) po += 2 * kPiDouble;
        if ((t.symmetry & kSymReciprocity) && ti > to) {
            std::swap(ti, to);
            std::swap(pi, po);
        }
        c[0] = ti;
        c[1] = pi;
        c[2] = to;
        c[3] = po;
    }
}

// Also reports the measured share of the cell's weight: where it is tiny, renormalizing
// over the few measured corners makes the result jump with the smallest angle change.
std::vector<double> ref_eval(const TableView& t, const double* wi, const double* wo, double* covered_out = nullptr) {
    std::vector<double> out(t.channels, 0.0);
    if (covered_out) *covered_out = 1.0;
    if (!(wi[2] > 0 && wo[2] > 0)) return out;
    double c[4];
    ref_coords(t, wi, wo, c);
    int cell[4];
    double frac[4];
    for (int a = 0; a < t.dims; ++a) {
        int i = 0;
        while (i + 2 < t.lengths[a] && c[a] >= t.knots[a][i + 1]) ++i;
        cell[a] = i;
        frac[a] = std::clamp((c[a] - t.knots[a][i]) / (double(t.knots[a][i + 1]) - t.knots[a][i]), 0.0, 1.0);
    }
    double covered = 0;
    for (int k = 0; k < (1 << t.dims); ++k) {
        double w = 1;
        size_t point = 0;
        for (int a = 0; a < t.dims; ++a) {
            const int upper = (k >> (t.dims - 1 - a)) & 1;
            w *= upper ? frac[a] : 1 - frac[a];
            point += size_t(cell[a] + upper) * t.strides[a];
        }
        if (t.coverage) w *= t.coverage[point];
        covered += w;
        for (int ch = 0; ch < t.channels; ++ch) out[ch] += w * t.values[point * t.channels + ch];
    }
    if (t.coverage) {
        for (double& v : out) v = covered > 0 ? v / covered : 0.0;
    }
    if (covered_out) *covered_out = covered;
    return out;
}

// Direction pairs: random over the hemisphere, a few below it, some on the grid's knots.
void make_pairs(size_t n, unsigned seed, std::vector<float>& wi, std::vector<float>& wo) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    auto dir = [&](std::vector<float>& out) {
        double z = u(rng);
        if (rng() % 40 == 0) z = -z;     // below the horizon
        if (rng() % 40 == 0) z = 1.0;    // the pole
        if (rng() % 40 == 0) z = 0.0;    // grazing
        const double phi = 2 * kPiDouble * u(rng), r = std::sqrt(std::max(0.0, 1 - z * z));
        out.push_back(float(r * std::cos(phi)));
        out.push_back(float(r * std::sin(phi)));
        out.push_back(float(z));
    };
    for (size_t i = 0; i < n; ++i) {
        dir(wi);
        dir(wo);
    }
}

// Neighbouring-pixel pairs: a slowly turning frame.
void make_coherent_pairs(size_t n, std::vector<float>& wi, std::vector<float>& wo) {
    for (size_t i = 0; i < n; ++i) {
        const double s = double(i) / n;
        const double ti = 0.2 + 1.2 * s, to = 1.3 - 1.1 * s, dp = 0.3 + 2.5 * s;
        wi.insert(wi.end(), {float(std::sin(ti)), 0.0f, float(std::cos(ti))});
        wo.insert(wo.end(), {float(std::sin(to) * std::cos(dp)), float(std::sin(to) * std::sin(dp)), float(std::cos(to))});
    }
}

struct Case {
    const char* name;
    Parametrization p;
    int channels;
    uint32_t symmetry;
    bool holes;
};

const Case kCases[] = {
    {"iso_rgb", Parametrization::Isotropic, 3, 0, false},
    {"iso_recip_spectral", Parametrization::Isotropic, 16, kSymReciprocity, false},
    {"halfdiff_merl_like", Parametrization::HalfDiff, 3, kSymReciprocity, true},
    {"halfdiff_mirror_mono", Parametrization::HalfDiff, 1, kSymReciprocity | kSymPhiMirror, false},
    {"aniso_rgb", Parametrization::Anisotropic, 3, 0, true},
    {"aniso_recip", Parametrization::Anisotropic, 3, kSymReciprocity, false},
};

std::vector<float> eval_with(int width, const TableView& v, const std::vector<float>& wi, const std::vector<float>& wo,
                             int threads = 1) {
    const size_t n = wi.size() / 3;
    std::vector<float> out(n * v.channels, -1.0f);
    eval_batch(v, wi.data(), wo.data(), out.data(), n, width, threads);
    return out;
}
}  // namespace

TEST(Eval, WideWidthsMatchScalarLaneByLane) {
    for (const Case& c : kCases) {
        SCOPED_TRACE(c.name);
        const Table t = make_table(c.p, c.channels, c.symmetry, c.holes);
        const PreparedTable prep = prepare(t);
        std::vector<float> wi, wo;
        make_pairs(20000, 3, wi, wo);
        make_coherent_pairs(4000, wi, wo);
        const auto r1 = eval_with(1, prep.view, wi, wo);
        for (int w : {4, 8, 16}) {
            if (!width_supported(w)) continue;
            const auto rw = eval_with(w, prep.view, wi, wo);
            for (size_t i = 0; i < r1.size(); ++i) {
                // the same operations in the same order at every width: bit for bit
                ASSERT_EQ(rw[i], r1[i]) << "width " << w << ", pair " << i / c.channels;
            }
        }
    }
}

TEST(Eval, ScalarMatchesDoublePrecisionReference) {
    for (const Case& c : kCases) {
        SCOPED_TRACE(c.name);
        const Table t = make_table(c.p, c.channels, c.symmetry, c.holes);
        const PreparedTable prep = prepare(t);
        std::vector<float> wi, wo;
        make_pairs(20000, 5, wi, wo);
        const auto r1 = eval_with(1, prep.view, wi, wo);
        double worst = 0;
        size_t worst_at = 0;
        for (size_t i = 0; i < wi.size() / 3; ++i) {
            const double dwi[3] = {wi[3 * i], wi[3 * i + 1], wi[3 * i + 2]};
            const double dwo[3] = {wo[3 * i], wo[3 * i + 1], wo[3 * i + 2]};
            double covered;
            const auto ref = ref_eval(prep.view, dwi, dwo, &covered);
            if (covered < 1e-3) continue;
            for (int ch = 0; ch < c.channels; ++ch) {
                const double err = std::fabs(r1[i * c.channels + ch] - ref[ch]) / std::max(std::fabs(ref[ch]), 0.05);
                if (err > worst) {
                    worst = err;
                    worst_at = i;
                }
            }
        }
        // Smooth tables: value error = gradient x angle error (<= 5e-7 rad) + float rounding.
        EXPECT_LT(worst, 2e-5) << "worst relative error " << worst << " at wi = (" << wi[3 * worst_at] << ", "
                               << wi[3 * worst_at + 1] << ", " << wi[3 * worst_at + 2] << "), wo = (" << wo[3 * worst_at]
                               << ", " << wo[3 * worst_at + 1] << ", " << wo[3 * worst_at + 2] << ")";
    }
}

TEST(Eval, AnyBatchLengthAndThreadsGiveTheSameValues) {
    const Table t = make_table(Parametrization::HalfDiff, 3, kSymReciprocity, true);
    const PreparedTable prep = prepare(t);
    std::vector<float> wi, wo;
    make_pairs(70001, 8, wi, wo);
    for (int w : {1, 4, 8, 16}) {
        if (!width_supported(w)) continue;
        const auto all = eval_with(w, prep.view, wi, wo, 1);
        const auto threaded = eval_with(w, prep.view, wi, wo, 2);
        ASSERT_EQ(all, threaded);
        for (size_t n : {0, 1, 2, 3, 5, 7, 9, 15, 17}) {
            std::vector<float> out(n * 3 + 3, -7.0f);
            eval_batch(prep.view, wi.data(), wo.data(), out.data(), n, w, 1);
            for (size_t i = 0; i < n * 3; ++i) ASSERT_EQ(out[i], all[i]) << "width " << w << " n " << n;
            for (size_t i = n * 3; i < out.size(); ++i) ASSERT_EQ(out[i], -7.0f) << "wrote past the end";
        }
    }
}

TEST(Eval, KnotsAreReproducedAndOutsideClamps) {
    const Table t = make_table(Parametrization::Isotropic, 3, 0, false);
    const PreparedTable prep = prepare(t);
    std::vector<float> wi, wo, want;
    for (size_t a = 1; a + 1 < t.axes[0].size(); a += 3)
        for (size_t b = 1; b + 1 < t.axes[1].size(); b += 4)
            for (size_t c = 1; c + 1 < t.axes[2].size(); c += 5) {
                const double ti = t.axes[0][a], to = t.axes[1][b], pd = t.axes[2][c];
                wi.insert(wi.end(), {float(std::sin(ti)), 0.0f, float(std::cos(ti))});
                wo.insert(wo.end(), {float(std::sin(to) * std::cos(pd)), float(std::sin(to) * std::sin(pd)), float(std::cos(to))});
                const size_t point = (a * t.axes[1].size() + b) * t.axes[2].size() + c;
                for (int ch = 0; ch < 3; ++ch) want.push_back(t.values[point * 3 + ch]);
            }
    for (int w : {1, 4, 8, 16}) {
        if (!width_supported(w)) continue;
        const auto got = eval_with(w, prep.view, wi, wo);
        for (size_t i = 0; i < got.size(); ++i) ASSERT_NEAR(got[i], want[i], 2e-5 * want[i]) << "knot " << i / 3;
    }
    // Below the horizon gives 0, for either direction.
    const std::vector<float> up = {0.0f, 0.6f, 0.8f}, down = {0.0f, 0.6f, -0.8f};
    for (int w : {1, 4, 8, 16}) {
        if (!width_supported(w)) continue;
        for (float v : eval_with(w, prep.view, up, down)) EXPECT_EQ(v, 0.0f);
        for (float v : eval_with(w, prep.view, down, up)) EXPECT_EQ(v, 0.0f);
    }
}

TEST(Eval, MissingCellsGiveZeroNotData) {
    Table t = make_table(Parametrization::Isotropic, 1, 0, false);
    t.valid.assign(t.point_count(), 0);  // nothing measured
    for (float& v : t.values) v = 0.0f;
    const PreparedTable prep = prepare(t);
    std::vector<float> wi, wo;
    make_pairs(1000, 4, wi, wo);
    for (int w : {1, 4, 8, 16}) {
        if (!width_supported(w)) continue;
        for (float v : eval_with(w, prep.view, wi, wo)) ASSERT_EQ(v, 0.0f);
    }
}

TEST(Eval, SearchFindsTheCell) {
    // 90 and 181 knots: the wide widths' window (2N knots in registers, brdf/search.h) then
    // fits inside the axis at every width, so coherent blocks take it.
    for (int count : {90, 181}) {
        SCOPED_TRACE(count);
        const std::vector<float> knots = irregular_axis(count, 0.0, kPiDouble / 2, 2.0);
        std::vector<float> xs = {-1.0f, 0.0f, knots[1], knots[45], knots[88], knots[89], 2.0f, std::nanf("")};
        std::mt19937 rng(3);
        std::uniform_real_distribution<float> u(-0.1f, 1.7f);
        for (int i = 0; i < 10000; ++i) xs.push_back(u(rng));
        for (int i = 0; i < 10000; ++i) xs.push_back(float(i) / 10000 * 1.6f);  // coherent
        // coherent runs broken by the cases a window must refuse: NaN, below and above the axis,
        // a jump across it, knots exactly at a window's edge
        for (int i = 0; i < 4000; ++i) {
            float x = 0.3f + float(i % 500) / 500 * 0.4f;
            if (i % 97 == 5) x = std::nanf("");
            if (i % 131 == 7) x = -0.5f;
            if (i % 151 == 9) x = 3.0f;
            if (i % 173 == 11) x = 1.5f - x;
            if (i % 59 == 13) x = knots[(i / 59) % count];
            xs.push_back(x);
        }
        // runs inside one cell (the search then tries that cell first) left by one lane: at the
        // cell's upper knot, at its lower one (inside), NaN, below and above the axis (inside
        // the end cells)
        for (int c : {0, 1, count / 2, count - 2}) {
            const float mid = 0.5f * (knots[c] + knots[c + 1]);
            for (float odd : {knots[c + 1], knots[c], std::nanf(""), -1.0f, 2.0f}) {
                for (int i = 0; i < 32; ++i) xs.push_back(mid);
                for (int i = 0; i < 16; ++i) xs.push_back(i == 5 ? odd : mid);
            }
        }
        for (int w : {1, 4, 8, 16}) {
            if (!width_supported(w)) continue;
            for (auto search : {kernels_for(w).search, kernels_for(w).search_thesis}) {
                std::vector<int32_t> cells(xs.size(), -5);
                search(knots.data(), int(knots.size()), xs.data(), cells.data(), xs.size());
                for (size_t i = 0; i < xs.size(); ++i) {
                    int want = int(std::upper_bound(knots.begin(), knots.end(), xs[i]) - knots.begin()) - 1;
                    want = std::clamp(want, 0, int(knots.size()) - 2);
                    if (std::isnan(xs[i])) want = 0;
                    ASSERT_EQ(cells[i], want) << "width " << w << " x=" << xs[i];
                }
            }
        }
    }
}

// A MERL-sized grid (90 x 46 x 181, finer than kCases' tables): at width 16 only axes of more
// than 32 knots take the windowed search and the lookups from registers (brdf/search.h), so
// they are checked here, on the pairs of a lit sphere scanned row by row (lanes that split
// near the middle knot, blocks that follow each other, lanes below the horizon at its rim),
// on slowly turning frames and on random pairs.
TEST(Eval, FineAxesMatchScalarLaneByLane) {
    Table t;
    t.parametrization = Parametrization::HalfDiff;
    t.channels = 3;
    t.channel_kind = ChannelKind::RGB;
    t.symmetry = kSymReciprocity;
    t.axes = {irregular_axis(90, 0, kPiDouble / 2, 2.0), irregular_axis(46, 0, kPiDouble / 2, 1.0),
              irregular_axis(181, 0, kPiDouble, 1.0)};
    const size_t points = t.axes[0].size() * t.axes[1].size() * t.axes[2].size();
    t.values.resize(points * 3);
    for (size_t i = 0; i < points; ++i) {
        const size_t p = i % t.axes[2].size(), d = i / t.axes[2].size() % t.axes[1].size();
        const size_t h = i / (t.axes[2].size() * t.axes[1].size());
        const double c[3] = {t.axes[0][h], t.axes[1][d], t.axes[2][p]};
        for (int ch = 0; ch < 3; ++ch) t.values[i * 3 + ch] = float(smooth(t.parametrization, c, ch));
    }
    t.check();
    const PreparedTable prep = prepare(t);
    std::vector<float> wi, wo;
    const int side = 160;
    const double light[3] = {0.5 / 0.9844, 0.6 / 0.9844, 0.62 / 0.9844};
    for (int row = 0; row < side; ++row)
        for (int col = 0; col < side; ++col) {
            const double x = (col + 0.5) / side * 2 - 1, y = 1 - (row + 0.5) / side * 2;
            if (x * x + y * y >= 0.999) continue;
            const double n[3] = {x, y, std::sqrt(1 - x * x - y * y)};
            // the frame of the bench's coherent pairs: t = n x (0, 1, 0), b = n x t
            double tx = -n[2], tz = n[0];
            const double tl = std::sqrt(tx * tx + tz * tz);
            tx /= tl;
            tz /= tl;
            const double b[3] = {n[1] * tz, n[2] * tx - n[0] * tz, -n[1] * tx};
            const double l[3] = {tx * light[0] + tz * light[2], b[0] * light[0] + b[1] * light[1] + b[2] * light[2],
                                 n[0] * light[0] + n[1] * light[1] + n[2] * light[2]};
            wi.insert(wi.end(), {float(l[0]), float(l[1]), float(l[2])});
            wo.insert(wo.end(), {float(tz), float(b[2]), float(n[2])});  // the view (0, 0, 1) in the frame
        }
    make_coherent_pairs(6000, wi, wo);
    make_pairs(6000, 9, wi, wo);
    const auto r1 = eval_with(1, prep.view, wi, wo);
    for (int w : {4, 8, 16}) {
        if (!width_supported(w)) continue;
        const auto rw = eval_with(w, prep.view, wi, wo);
        for (size_t i = 0; i < r1.size(); ++i) ASSERT_EQ(rw[i], r1[i]) << "width " << w << ", pair " << i / 3;
    }
}

TEST(Eval, ForcedWidthsAreCheckedAgainstTheCpu) {
    EXPECT_THROW(resolve_width(3), std::invalid_argument);
    EXPECT_EQ(resolve_width(1), 1);
    EXPECT_GE(default_width(), 1);
}
