// The Sobol generator and its Owen scramble (render/sobol.h), and the sampler's numbers
// (render/sample_numbers.h): net properties, uniformity, the independent numbers unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "render/sample_numbers.h"
#include "render/sobol.h"

namespace {
using namespace patina;

// Every elementary interval [i 2^-a, (i+1) 2^-a) x [j 2^-b, (j+1) 2^-b) with a + b = m holds
// exactly one of the 2^m points (a (0, m, 2)-net), looking at the top bits of x and y.
bool is_02_net(const std::vector<uint32_t>& x, const std::vector<uint32_t>& y, int m) {
    for (int a = 0; a <= m; ++a) {
        const int b = m - a;
        std::vector<int> count(size_t{1} << m, 0);
        for (size_t k = 0; k < x.size(); ++k) {
            const uint32_t i = a == 0 ? 0 : x[k] >> (32 - a), j = b == 0 ? 0 : y[k] >> (32 - b);
            if (++count[(i << b) | j] > 1) return false;
        }
    }
    return true;
}

TEST(Sobol, FirstPointsAreTheKnownOnes) {
    // dimension 0 is van der Corput (bit-reversed index); dimension 1's first points are
    // 0, 1/2, 3/4, 1/4 (direct order: point 3 = V0 ^ V1 = 1/2 ^ 3/4)
    EXPECT_EQ(sobol::point_bits(1, 0), 0x80000000u);
    EXPECT_EQ(sobol::point_bits(2, 0), 0x40000000u);
    EXPECT_EQ(sobol::point_bits(6, 0), 0x60000000u);
    EXPECT_EQ(sobol::point_bits(0, 5), 0u);
    EXPECT_EQ(sobol::point_bits(1, 1), 0x80000000u);
    EXPECT_EQ(sobol::point_bits(2, 1), 0xc0000000u);
    EXPECT_EQ(sobol::point_bits(3, 1), 0x40000000u);
}

TEST(Sobol, EveryDimensionIsStratifiedIn1D) {
    // each dimension alone is a (0, 1)-sequence: any aligned block of 2^m points has one
    // point in each interval of width 2^-m, scrambled or not
    for (int d = 0; d < sobol::kDimensions; ++d)
        for (int m : {1, 4, 7}) {
            const uint32_t n = 1u << m, first = 3 * n;
            std::vector<int> plain(n, 0), scrambled(n, 0);
            for (uint32_t i = first; i < first + n; ++i) {
                const uint32_t x = sobol::point_bits(i, d);
                ++plain[x >> (32 - m)];
                ++scrambled[sobol::owen_scramble(x, 0x1234567u + d) >> (32 - m)];
            }
            for (uint32_t k = 0; k < n; ++k) {
                ASSERT_EQ(plain[k], 1) << "dimension " << d << " m " << m;
                ASSERT_EQ(scrambled[k], 1) << "dimension " << d << " m " << m;
            }
        }
}

TEST(Sobol, TheFirstTwoDimensionsAreA02NetScrambledOrNot) {
    for (int m = 1; m <= 10; ++m)
        for (uint32_t block : {0u, 1u, 5u}) {
            const uint32_t n = 1u << m;
            for (uint32_t seed : {0u, 1u, 0xdeadbeefu}) {
                std::vector<uint32_t> x, y, sx, sy;
                for (uint32_t i = block * n; i < (block + 1) * n; ++i) {
                    x.push_back(sobol::point_bits(i, 0));
                    y.push_back(sobol::point_bits(i, 1));
                    sx.push_back(sobol::owen_scramble(x.back(), hash_u32(seed)));
                    sy.push_back(sobol::owen_scramble(y.back(), hash_u32(seed + 1)));
                }
                ASSERT_TRUE(is_02_net(x, y, m)) << "m " << m << " block " << block;
                ASSERT_TRUE(is_02_net(sx, sy, m)) << "m " << m << " block " << block << " seed " << seed;
            }
        }
}

TEST(Sobol, TheScrambleIsNestedAndABijectionOfTheTopBits) {
    // values that share their top j bits still share them scrambled (the tree structure),
    // and the top 24 bits are permuted (no two values of a 2^12 grid collide)
    const uint32_t seed = 0x9e3779b9u;
    std::vector<int> seen(1 << 12, 0);
    for (uint32_t k = 0; k < (1u << 12); ++k) {
        const uint32_t x = k << 20;
        ++seen[sobol::owen_scramble(x, seed) >> 20];
        for (int j = 1; j < 24; ++j) {
            const uint32_t y = x ^ (1u << (31 - j));  // first differs from x at bit 31 - j
            const uint32_t sx = sobol::owen_scramble(x, seed), sy = sobol::owen_scramble(y, seed);
            ASSERT_EQ(sx >> (32 - j), sy >> (32 - j)) << "x " << x << " j " << j;
            ASSERT_NE((sx >> (31 - j)) & 1u, (sy >> (31 - j)) & 1u);
        }
    }
    for (int c : seen) ASSERT_EQ(c, 1);
    EXPECT_EQ(sobol::owen_scramble(0x12345678u, seed) & 0xffu, 0x78u);  // the bits a float drops stay
}

TEST(Sobol, ScrambledPointsAreUniformOverSeeds) {
    // a fixed point scrambled by many seeds: uniform in [0, 1) (16 bins, a chi-square bound
    // far above its 99.99 % point for 15 degrees of freedom, 44)
    for (uint32_t x : {0u, 0x80000000u, 0x5a5a5a5au}) {
        std::vector<int> bins(16, 0);
        const int n = 1 << 14;
        for (int s = 0; s < n; ++s) ++bins[sobol::owen_scramble(x, hash_u32(s)) >> 28];
        double chi2 = 0;
        for (int b : bins) chi2 += (b - n / 16.0) * (b - n / 16.0) / (n / 16.0);
        EXPECT_LT(chi2, 44.0) << "x " << x;
    }
}

TEST(SampleNumbers, IndependentNumbersAreTheCounterHashes) {
    // the independent sampler draws rng.h's numbers of (path key, dimension), as before
    for (uint32_t pixel : {0u, 7u, 123456u})
        for (uint32_t s : {0u, 1u, 99u})
            for (int bounce = 0; bounce < 4; ++bounce)
                for (RandomDim d : {kDimPixelX, kDimLensV, kDimLightU, kDimBsdfPick, kDimRoulette}) {
                    const float want = bounce_uniform(path_key(42, pixel, s), bounce, d);
                    ASSERT_EQ(sample_uniform(SamplerKind::Independent, stream_key(42, pixel), s, bounce, d), want);
                }
}

TEST(SampleNumbers, EachUseHasItsOwnSobolDimension) {
    // the camera's uses are dimensions 0-3 of the first bounce, then seven a bounce, each
    // dimension of the table used once; uses past it are padded (kNoSobolDim)
    std::vector<int> used(sobol::kDimensions, 0);
    int covered = 0;
    for (int bounce = 0; bounce < 40; ++bounce)
        for (int d = 0; d <= static_cast<int>(kDimRoulette); ++d) {
            const uint32_t dim = sobol_dimension(bounce, static_cast<RandomDim>(d));
            if (bounce > 0 && d < static_cast<int>(kDimLightPick)) {
                EXPECT_EQ(dim, kNoSobolDim);
                continue;
            }
            if (dim == kNoSobolDim) continue;
            ASSERT_LT(dim, static_cast<uint32_t>(sobol::kDimensions));
            ASSERT_EQ(++used[dim], 1) << "dimension " << dim;
            ++covered;
        }
    EXPECT_EQ(covered, sobol::kDimensions);
    EXPECT_EQ(sobol_dimension(0, kDimPixelX), 0u);
    EXPECT_EQ(sobol_dimension(0, kDimPixelY), 1u);
    EXPECT_EQ(sobol_dimension(40, kDimLightU), kNoSobolDim);
}

TEST(SampleNumbers, SobolNumbersAreAPixelsStratifiedSequence) {
    // a pixel's first 64 samples: pixel positions a (0, 6, 2)-net, every use stratified in
    // 64 intervals; another pixel (stream) draws other numbers
    const uint32_t key = stream_key(7, 1234), other = stream_key(7, 1235);
    std::vector<uint32_t> x, y;
    for (int bounce = 0; bounce < 3; ++bounce)
        for (RandomDim d : {kDimLensU, kDimLightPick, kDimLightV, kDimBsdfU, kDimRoulette}) {
            if (bounce > 0 && d == kDimLensU) continue;
            std::vector<int> count(64, 0);
            int same = 0;
            for (uint32_t i = 0; i < 64; ++i) {
                const float u = sample_uniform(SamplerKind::Sobol, key, i, bounce, d);
                ASSERT_GE(u, 0.0f);
                ASSERT_LT(u, 1.0f);
                ++count[static_cast<int>(u * 64)];
                same += u == sample_uniform(SamplerKind::Sobol, other, i, bounce, d);
            }
            for (int c : count) ASSERT_EQ(c, 1) << "bounce " << bounce << " use " << d;
            EXPECT_LT(same, 4);
        }
    for (uint32_t i = 0; i < 64; ++i) {
        x.push_back(static_cast<uint32_t>(sample_uniform(SamplerKind::Sobol, key, i, 0, kDimPixelX) * 16777216.0f) << 8);
        y.push_back(static_cast<uint32_t>(sample_uniform(SamplerKind::Sobol, key, i, 0, kDimPixelY) * 16777216.0f) << 8);
    }
    EXPECT_TRUE(is_02_net(x, y, 6));
}

}  // namespace
