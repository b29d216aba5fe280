// Lane-by-lane tests of the SIMD vocabulary and fast math at width PATINA_TEST_WIDTH,
// against the width-1 instantiation of the same functions. Included by
// tests/cpp/core/simd/test_simd_w4.cpp (-msse4.1) and tests/cpp/core/simd/test_simd_w8.cpp (-mavx2 -mfma).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "core/simd/fastmath.h"
#include "core/simd/weighted_rows.h"
#include "tests/cpp/lane_width_fixture.h"
#include "tests/cpp/test_values.h"

#define PATINA_CAT2(a, b) a##b
#define PATINA_CAT(a, b) PATINA_CAT2(a, b)
#define LANE_SUITE PATINA_CAT(SimdLanes_w, PATINA_TEST_WIDTH)
#define LANE_TEST(name) TEST_F(LANE_SUITE, name)

// a width the CPU cannot run is skipped by the fixture, before any of its code runs
using LANE_SUITE = patina::test::LaneWidth<PATINA_TEST_WIDTH>;

namespace {
using namespace patina;
constexpr int N = PATINA_TEST_WIDTH;
using F = vfloat<N>;
using I = vint<N>;
using B = vbool<N>;

bool same_float(float a, float b) {
    if (std::isnan(a) && std::isnan(b)) return true;
    uint32_t ua, ub;
    std::memcpy(&ua, &a, 4);
    std::memcpy(&ub, &b, 4);
    return ua == ub;
}

// Runs op on N lanes at a time and compares each lane with op at width 1.
// `ulps` allows the last-bit differences FMA brings at width 8.
template <class WideOp, class ScalarOp>
void check_unary(const std::vector<float>& xs, WideOp wide, ScalarOp scalar, float rel_tol, float abs_tol) {
    for (size_t i = 0; i + N <= xs.size(); i += N) {
        const F r = wide(load_n<N>(&xs[i]));
        for (int j = 0; j < N; ++j) {
            const float want = scalar(xs[i + j]);
            const float got = patina::lane(r, j);
            if (rel_tol == 0 && abs_tol == 0) {
                ASSERT_TRUE(same_float(got, want)) << "x=" << xs[i + j] << " lane " << j << " got " << got << " want " << want;
            } else if (std::isnan(want) || std::isinf(want)) {
                ASSERT_TRUE(same_float(got, want)) << "x=" << xs[i + j] << " lane " << j;
            } else {
                ASSERT_NEAR(got, want, abs_tol + rel_tol * std::fabs(want)) << "x=" << xs[i + j] << " lane " << j;
            }
        }
    }
}

template <class WideOp, class ScalarOp>
void check_binary(const std::vector<float>& ys, const std::vector<float>& xs, WideOp wide, ScalarOp scalar,
                  float abs_tol) {
    for (size_t i = 0; i + N <= xs.size(); i += N) {
        const F r = wide(load_n<N>(&ys[i]), load_n<N>(&xs[i]));
        for (int j = 0; j < N; ++j) {
            const float want = scalar(ys[i + j], xs[i + j]);
            const float got = patina::lane(r, j);
            if (abs_tol == 0 || std::isnan(want))
                ASSERT_TRUE(same_float(got, want)) << "y=" << ys[i + j] << " x=" << xs[i + j] << " lane " << j;
            else
                ASSERT_NEAR(got, want, abs_tol) << "y=" << ys[i + j] << " x=" << xs[i + j] << " lane " << j;
        }
    }
}

// madd rounds twice at every width, so fast math must match width 1 bit for bit.
constexpr float kMathAbsTol = 0.0f;

std::vector<float> padded(std::vector<float> v) {
    while (v.size() % N) v.push_back(0.5f);
    return v;
}
}  // namespace

LANE_TEST(ArithmeticMatchesScalar) {
    const auto xs = padded(test_values::mixed(4096, 11));
    const auto ys = padded(test_values::mixed(4096, 12));
    check_binary(ys, xs, [](F a, F b) { return a + b; }, [](float a, float b) { return a + b; }, 0);
    check_binary(ys, xs, [](F a, F b) { return a - b; }, [](float a, float b) { return a - b; }, 0);
    check_binary(ys, xs, [](F a, F b) { return a * b; }, [](float a, float b) { return a * b; }, 0);
    check_binary(ys, xs, [](F a, F b) { return a / b; }, [](float a, float b) { return a / b; }, 0);
    check_binary(ys, xs, [](F a, F b) { return patina::min(a, b); }, [](float a, float b) { return patina::min(a, b); }, 0);
    check_binary(ys, xs, [](F a, F b) { return patina::max(a, b); }, [](float a, float b) { return patina::max(a, b); }, 0);
    check_binary(ys, xs, [](F a, F b) { return patina::copysign(a, b); }, [](float a, float b) { return patina::copysign(a, b); }, 0);
    check_binary(ys, xs, [](F a, F b) { return patina::select(a < b, a, b); }, [](float a, float b) { return a < b ? a : b; }, 0);
    check_binary(ys, xs, [](F a, F b) { return patina::select(a >= b, F(1.0f), F(0.0f)); },
                 [](float a, float b) { return a >= b ? 1.0f : 0.0f; }, 0);
    check_binary(ys, xs, [](F a, F b) { return patina::select(a == b, F(1.0f), F(0.0f)); },
                 [](float a, float b) { return a == b ? 1.0f : 0.0f; }, 0);
    check_binary(ys, xs, [](F a, F b) { return patina::select(a != b, F(1.0f), F(0.0f)); },
                 [](float a, float b) { return a != b ? 1.0f : 0.0f; }, 0);
    check_unary(xs, [](F a) { return patina::abs(a); }, [](float a) { return std::fabs(a); }, 0, 0);
    check_unary(xs, [](F a) { return -a; }, [](float a) { return -a; }, 0, 0);
    check_unary(xs, [](F a) { return patina::floor(a); }, [](float a) { return std::floor(a); }, 0, 0);
    check_unary(xs, [](F a) { return patina::sqrt_exact(a); }, [](float a) { return std::sqrt(a); }, 0, 0);
    check_unary(xs, [](F a) { return patina::select(patina::isnan(a), F(1.0f), F(0.0f)); },
                [](float a) { return std::isnan(a) ? 1.0f : 0.0f; }, 0, 0);
    check_unary(xs, [](F a) { return patina::select(patina::signbit(a), F(1.0f), F(0.0f)); },
                [](float a) { return std::signbit(a) ? 1.0f : 0.0f; }, 0, 0);
}

LANE_TEST(FusedMaddWithinOneRounding) {
    const auto a = padded(test_values::uniform(4096, -100.0f, 100.0f, 21));
    const auto b = padded(test_values::uniform(4096, -100.0f, 100.0f, 22));
    for (size_t i = 0; i + N <= a.size(); i += N) {
        const F r = patina::fmadd(load_n<N>(&a[i]), load_n<N>(&b[i]), F(3.0f));
        for (int j = 0; j < N; ++j) {
            const double exact = double(a[i + j]) * double(b[i + j]) + 3.0;
            ASSERT_NEAR(patina::lane(r, j), exact, 2.5e-7 * std::fabs(exact) + 1e-6);
        }
    }
}

LANE_TEST(IntegerOpsAndMasks) {
    std::mt19937 rng(5);
    std::uniform_int_distribution<int32_t> dist(-100000, 100000);
    int32_t a[N], b[N];
    float fa[N];
    for (int rep = 0; rep < 200; ++rep) {
        for (int j = 0; j < N; ++j) {
            a[j] = dist(rng);
            b[j] = dist(rng);
            fa[j] = float(a[j]) * 0.37f;
        }
        const I va = load_n<N>(a), vb = load_n<N>(b);
        // At width 1 vint is int32_t, and shifting a negative int32_t left is undefined (C++17);
        // the SIMD shifts (pslld) are defined for every bit pattern, so only they shift negatives.
        const I shl_in = N == 1 ? patina::select(va < I(0), I(0) - va, va) : va;
        const I sum = va + vb, diff = va - vb, prod = va * I(3), mn = patina::min(va, vb), mx = patina::max(va, vb);
        const I sel = patina::select(va < vb, va, vb), shl = shl_in << 2, shr = va >> 3;
        const I trunc = patina::to_int_trunc(load_n<N>(fa));
        const I x = va ^ vb, logical = patina::srl(va, 7), wrapped = patina::mul_wrap(va, I(int32_t(0x846ca68b)));
        const B lt = va < vb, eq = va == vb;
        const int mask = patina::movemask(lt);
        int expect_mask = 0;
        for (int j = 0; j < N; ++j) {
            EXPECT_EQ(patina::lane(sum, j), a[j] + b[j]);
            EXPECT_EQ(patina::lane(diff, j), a[j] - b[j]);
            EXPECT_EQ(patina::lane(prod, j), a[j] * 3);
            EXPECT_EQ(patina::lane(mn, j), std::min(a[j], b[j]));
            EXPECT_EQ(patina::lane(mx, j), std::max(a[j], b[j]));
            EXPECT_EQ(patina::lane(sel, j), a[j] < b[j] ? a[j] : b[j]);
            EXPECT_EQ(patina::lane(shl, j), (N == 1 ? std::abs(a[j]) : a[j]) * 4);
            EXPECT_EQ(patina::lane(shr, j), a[j] >> 3);
            EXPECT_EQ(patina::lane(trunc, j), static_cast<int32_t>(fa[j]));
            EXPECT_EQ(patina::lane(x, j), a[j] ^ b[j]);
            EXPECT_EQ(patina::lane(logical, j), static_cast<int32_t>(static_cast<uint32_t>(a[j]) >> 7));
            EXPECT_EQ(patina::lane(wrapped, j), static_cast<int32_t>(static_cast<uint32_t>(a[j]) * 0x846ca68bu));
            EXPECT_EQ(patina::lane(lt, j), a[j] < b[j]);
            EXPECT_EQ(patina::lane(eq, j), a[j] == b[j]);
            expect_mask |= (a[j] < b[j]) << j;
        }
        EXPECT_EQ(mask, expect_mask);
        EXPECT_EQ(patina::any(lt), expect_mask != 0);
        EXPECT_EQ(patina::all(lt), expect_mask == (1 << N) - 1);
        EXPECT_EQ(patina::none(lt), expect_mask == 0);
        EXPECT_EQ(patina::movemask(patina::andnot(lt, B(true))), ((1 << N) - 1) & ~expect_mask);
        EXPECT_EQ(patina::movemask(lt | eq), patina::movemask(lt) | patina::movemask(eq));
        EXPECT_EQ(patina::movemask(lt & eq), 0);
        EXPECT_EQ(patina::movemask(lt ^ B(true)), ((1 << N) - 1) & ~expect_mask);
        EXPECT_EQ(patina::movemask(!lt), ((1 << N) - 1) & ~expect_mask);
    }
}

LANE_TEST(GatherReadsEveryLane) {
    std::vector<float> table(1000);
    for (size_t i = 0; i < table.size(); ++i) table[i] = float(i) * 0.5f + 1.0f;
    std::mt19937 rng(9);
    std::uniform_int_distribution<int32_t> dist(0, 999);
    for (int rep = 0; rep < 200; ++rep) {
        int32_t idx[N];
        float active_f[N];
        for (int j = 0; j < N; ++j) {
            idx[j] = dist(rng);
            active_f[j] = float(rng() & 1);
        }
        const I vi = load_n<N>(idx);
        const B active = load_n<N>(active_f) > F(0.5f);
        const F g = patina::gather(table.data(), vi);
        const F gm = patina::gather(table.data(), vi, active);
        for (int j = 0; j < N; ++j) {
            EXPECT_EQ(patina::lane(g, j), table[idx[j]]);
            EXPECT_EQ(patina::lane(gm, j), active_f[j] > 0.5f ? table[idx[j]] : 0.0f);
        }
    }
}

// The RGB corner interpolation (weighted_rows3): every lane the width-1 sum's bits, for 4, 8 and
// 16 corners, rows anywhere in the array (the last one against its padding float), weights
// that are 0, 1, subnormal or negative, and every count of lanes written.
namespace {
template <int K>
void check_weighted_rows(std::mt19937& rng) {
    constexpr int kRows = 300;
    std::vector<float> values(3 * kRows + 1);
    std::uniform_real_distribution<float> u(-2.0f, 2.0f);
    for (auto& v : values) v = u(rng);
    values.back() = std::numeric_limits<float>::quiet_NaN();  // the padding float: read, never used
    const float odd_weights[] = {0.0f, 1.0f, -0.0f, 1e-40f, -3.5f};
    for (int rep = 0; rep < 100; ++rep) {
        int32_t offset[K], row[N];
        float weight[K][N], norm[N];
        for (int k = 0; k < K; ++k) offset[k] = 3 * int32_t(rng() % 40);
        for (int j = 0; j < N; ++j) {
            row[j] = 3 * int32_t(rng() % (kRows - 40));
            norm[j] = u(rng);
            for (int k = 0; k < K; ++k) weight[k][j] = rng() % 4 ? u(rng) : odd_weights[rng() % 5];
        }
        if (rep == 0) {  // corner 0 of lane 0 on the last row
            row[0] = 3 * (kRows - 40);
            offset[0] = 3 * 39;
        }
        F w[K];
        for (int k = 0; k < K; ++k) w[k] = load_n<N>(weight[k]);
        const int lanes = rep % 3 == 1 ? 1 + int(rng() % N) : N;
        std::vector<float> out(3 * N + 1, -7.0f);
        weighted_rows3<N, K>(values.data(), load_n<N>(row), offset, w, load_n<N>(norm), out.data(), lanes);
        for (int j = 0; j < N; ++j)
            for (int c = 0; c < 3; ++c) {
                float want = 0.0f;
                for (int k = 0; k < K; ++k) want = weight[k][j] * values[row[j] + offset[k] + c] + want;
                want = want * norm[j];
                const float got = out[3 * j + c];
                if (j < lanes)
                    ASSERT_TRUE(same_float(got, want))
                        << K << " corners, lane " << j << " channel " << c << ": " << got << " want " << want;
                else
                    ASSERT_EQ(got, -7.0f) << "lane " << j << " beyond the " << lanes << " written";
            }
        ASSERT_EQ(out[3 * N], -7.0f);
    }
}
}  // namespace

LANE_TEST(WeightedRowsMatchScalar) {
    std::mt19937 rng(17);
    check_weighted_rows<4>(rng);
    check_weighted_rows<8>(rng);
    check_weighted_rows<16>(rng);
}

LANE_TEST(FastMathMatchesScalar) {
    const auto unit = padded(test_values::with_specials(test_values::uniform(1 << 16, -1.0f, 1.0f, 31)));
    const auto wide = padded(test_values::mixed(1 << 16, 32));
    const auto wide2 = padded(test_values::mixed(1 << 16, 33));
    check_unary(unit, [](F x) { return patina::fast_acos(x); }, [](float x) { return patina::fast_acos(x); }, 0, kMathAbsTol);
    check_unary(unit, [](F x) { return patina::fast_asin(x); }, [](float x) { return patina::fast_asin(x); }, 0, kMathAbsTol);
    check_unary(wide, [](F x) { return patina::fast_atan(x); }, [](float x) { return patina::fast_atan(x); }, 0, kMathAbsTol);
    check_binary(wide2, wide, [](F y, F x) { return patina::fast_atan2(y, x); }, [](float y, float x) { return patina::fast_atan2(y, x); },
                 kMathAbsTol);
    check_unary(wide, [](F x) { return patina::fast_sqrt(x); }, [](float x) { return patina::fast_sqrt(x); }, 0, 0);
}

LANE_TEST(ReciprocalsWithinStatedBound) {
    // The wide rcp / rsqrt refine a hardware estimate: within 3e-7 relative of width 1
    // for normal inputs, exact on the special values.
    auto xs = test_values::log_uniform(1 << 16, -120.0f, 120.0f, 41);
    std::vector<float> neg;
    for (float x : xs) neg.push_back(-x);
    check_unary(padded(xs), [](F x) { return patina::fast_rcp(x); }, [](float x) { return patina::fast_rcp(x); }, 3e-7f, 0.0f);
    check_unary(padded(neg), [](F x) { return patina::fast_rcp(x); }, [](float x) { return patina::fast_rcp(x); }, 3e-7f, 0.0f);
    check_unary(padded(xs), [](F x) { return patina::fast_rsqrt(x); }, [](float x) { return patina::fast_rsqrt(x); }, 3e-7f, 0.0f);
    const float inf = std::numeric_limits<float>::infinity();
    const std::vector<float> specials = padded({0.0f, -0.0f, inf, -inf, std::nanf("")});
    check_unary(specials, [](F x) { return patina::fast_rcp(x); }, [](float x) { return patina::fast_rcp(x); }, 3e-7f, 0);
    check_unary(padded({0.0f, -0.0f, inf, -1.0f, std::nanf("")}), [](F x) { return patina::fast_rsqrt(x); },
                [](float x) { return patina::fast_rsqrt(x); }, 3e-7f, 0);
}

namespace {
// Maximum absolute error of op over xs against the double-precision reference.
template <class WideOp, class Ref>
double max_error(const std::vector<float>& xs, WideOp op, Ref ref) {
    double worst = 0;
    for (size_t i = 0; i + N <= xs.size(); i += N) {
        const F r = op(load_n<N>(&xs[i]));
        for (int j = 0; j < N; ++j) worst = std::max(worst, std::fabs(double(patina::lane(r, j)) - ref(double(xs[i + j]))));
    }
    return worst;
}

std::vector<float> dense_unit_sweep() {
    std::vector<float> xs;
    const int steps = 1 << 22;
    for (int i = 0; i <= steps; ++i) xs.push_back(-1.0f + 2.0f * float(i) / float(steps));
    // every float in the last 2^16 ulps below +1 and above -1, where acos is steepest
    float a = 1.0f, b = -1.0f;
    for (int i = 0; i < (1 << 16); ++i) {
        xs.push_back(a);
        xs.push_back(b);
        a = std::nextafter(a, 0.0f);
        b = std::nextafter(b, 0.0f);
    }
    return padded(xs);
}
}  // namespace

// The bounds fastmath.h states, enforced against double precision.
LANE_TEST(FastMathErrorBounds) {
    const auto unit = dense_unit_sweep();
    EXPECT_LE(max_error(unit, [](F x) { return patina::fast_acos(x); }, [](double x) { return std::acos(x); }), 5e-7);
    EXPECT_LE(max_error(unit, [](F x) { return patina::fast_asin(x); }, [](double x) { return std::asin(x); }), 4e-7);
    auto wide = test_values::log_uniform(1 << 20, -40.0f, 40.0f, 51);
    for (size_t i = 0; i < wide.size(); i += 2) wide[i] = -wide[i];
    wide = padded(wide);
    EXPECT_LE(max_error(wide, [](F x) { return patina::fast_atan(x); }, [](double x) { return std::atan(x); }), 4e-7);
    EXPECT_LE(max_error(unit, [](F x) { return patina::fast_atan(x); }, [](double x) { return std::atan(x); }), 4e-7);

    // atan2 on a dense ring of angles at several radii, and on random pairs
    std::vector<float> ys, xs;
    for (int i = 0; i < (1 << 20); ++i) {
        const double t = -3.14159265358979 + 6.28318530717958 * (i + 0.5) / (1 << 20);
        const double r = std::ldexp(1.0, (i % 61) - 30);
        ys.push_back(float(r * std::sin(t)));
        xs.push_back(float(r * std::cos(t)));
    }
    const auto ry = test_values::mixed(1 << 18, 61), rx = test_values::mixed(1 << 18, 62);
    ys.insert(ys.end(), ry.begin(), ry.end());
    xs.insert(xs.end(), rx.begin(), rx.end());
    ys = padded(ys);
    xs = padded(xs);
    double worst = 0;
    for (size_t i = 0; i + N <= xs.size(); i += N) {
        const F r = patina::fast_atan2(load_n<N>(&ys[i]), load_n<N>(&xs[i]));
        for (int j = 0; j < N; ++j) {
            const double want = std::atan2(double(ys[i + j]), double(xs[i + j]));
            const double got = patina::lane(r, j);
            if (std::isnan(want)) {
                EXPECT_TRUE(std::isnan(got));
                continue;
            }
            worst = std::max(worst, std::fabs(got - want));
        }
    }
    EXPECT_LE(worst, 5e-7);
}

// Special values: the C library's answers, signed zeros included.
LANE_TEST(FastMathSpecialValues) {
    const auto s = test_values::specials();
    for (float x : s) {
        float xs[N];
        for (int j = 0; j < N; ++j) xs[j] = x;
        const F v = load_n<N>(xs);
        const float acos_got = patina::lane(patina::fast_acos(v), 0), asin_got = patina::lane(patina::fast_asin(v), 0), atan_got = patina::lane(patina::fast_atan(v), 0);
        if (std::isnan(x) || std::fabs(x) > 1) {
            EXPECT_TRUE(std::isnan(acos_got)) << x;
            EXPECT_TRUE(std::isnan(asin_got)) << x;
        } else {
            EXPECT_NEAR(acos_got, std::acos(double(x)), 5e-7) << x;
            EXPECT_NEAR(asin_got, std::asin(double(x)), 4e-7) << x;
            EXPECT_EQ(std::signbit(asin_got), std::signbit(x)) << x;
        }
        if (std::isnan(x)) EXPECT_TRUE(std::isnan(atan_got));
        else {
            EXPECT_NEAR(atan_got, std::atan(double(x)), 4e-7) << x;
            EXPECT_EQ(std::signbit(atan_got), std::signbit(x)) << x;
        }
        for (float y : s) {
            float ys[N];
            for (int j = 0; j < N; ++j) ys[j] = y;
            const float got = patina::lane(patina::fast_atan2(load_n<N>(ys), v), 0);
            const double want = std::atan2(double(y), double(x));
            if (std::isnan(want)) {
                EXPECT_TRUE(std::isnan(got)) << "atan2(" << y << ", " << x << ")";
            } else {
                EXPECT_NEAR(got, want, 5e-7) << "atan2(" << y << ", " << x << ")";
                EXPECT_EQ(std::signbit(got), std::signbit(want)) << "atan2(" << y << ", " << x << ")";
            }
        }
    }
}

// fast_sincos against double over several periods, and the same bits at every width.
LANE_TEST(FastSinCos) {
    auto xs = test_values::uniform(1 << 18, -100.0f, 100.0f, 71);
    for (int i = 0; i <= 4096; ++i) xs.push_back(6.2831853f * float(i) / 4096.0f);
    xs = padded(xs);
    double worst = 0;
    for (size_t i = 0; i + N <= xs.size(); i += N) {
        F s, c;
        patina::fast_sincos(load_n<N>(&xs[i]), s, c);
        for (int j = 0; j < N; ++j) {
            worst = std::max(worst, std::fabs(double(patina::lane(s, j)) - std::sin(double(xs[i + j]))));
            worst = std::max(worst, std::fabs(double(patina::lane(c, j)) - std::cos(double(xs[i + j]))));
            float s1, c1;
            patina::fast_sincos(xs[i + j], s1, c1);
            ASSERT_TRUE(same_float(patina::lane(s, j), s1) && same_float(patina::lane(c, j), c1)) << xs[i + j];
        }
    }
    EXPECT_LE(worst, 5e-7);
}

LANE_TEST(FastLogExp) {
    auto xs = test_values::log_uniform(1 << 18, -149.0f, 127.0f, 81);
    for (int i = 0; i < 4096; ++i) xs.push_back(0.5f + float(i) / 2048.0f);  // around 1
    xs = padded(xs);
    double worst_log = 0, worst_exp = 0;
    for (size_t i = 0; i + N <= xs.size(); i += N) {
        const F l = patina::fast_log(load_n<N>(&xs[i]));
        for (int j = 0; j < N; ++j) {
            const double want = std::log(double(xs[i + j]));
            worst_log = std::max(worst_log, std::fabs(patina::lane(l, j) - want) / std::max(1.0, std::fabs(want)));
            ASSERT_TRUE(same_float(patina::lane(l, j), patina::fast_log(xs[i + j])));
        }
    }
    const auto es = padded(test_values::uniform(1 << 18, -87.0f, 87.0f, 82));
    for (size_t i = 0; i + N <= es.size(); i += N) {
        const F e = patina::fast_exp(load_n<N>(&es[i]));
        for (int j = 0; j < N; ++j) {
            const double want = std::exp(double(es[i + j]));
            worst_exp = std::max(worst_exp, std::fabs(patina::lane(e, j) - want) / want);
            ASSERT_TRUE(same_float(patina::lane(e, j), patina::fast_exp(es[i + j])));
        }
    }
    EXPECT_LE(worst_log, 2e-7);
    EXPECT_LE(worst_exp, 3e-7);
    const float inf = std::numeric_limits<float>::infinity();
    EXPECT_EQ(patina::fast_log(0.0f), -inf);
    EXPECT_EQ(patina::fast_log(inf), inf);
    EXPECT_TRUE(std::isnan(patina::fast_log(-1.0f)));
    EXPECT_TRUE(std::isnan(patina::fast_log(std::nanf(""))));
    EXPECT_EQ(patina::fast_exp(100.0f), inf);
    EXPECT_EQ(patina::fast_exp(-100.0f), 0.0f);
    EXPECT_EQ(patina::fast_exp(0.0f), 1.0f);
}
