// The Sobol generator and its Owen scramble (render/samplers/sobol.h), and the sampler's numbers
// (render/samplers/sample_numbers.h): net properties, uniformity, the independent numbers unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "render/samplers/sample_numbers.h"
#include "render/samplers/sobol.h"

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
    EXPECT_EQ(sobol::point_bits(0, 1), 0u);
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
    // the independent sampler draws render/samplers/rng.h's numbers of (path key, dimension), as before
    for (uint32_t pixel : {0u, 7u, 123456u})
        for (uint32_t s : {0u, 1u, 99u})
            for (int bounce = 0; bounce < 4; ++bounce)
                for (RandomDim d : {kDimPixelX, kDimLensV, kDimLightU, kDimBsdfPick, kDimRoulette}) {
                    const float want = bounce_uniform(path_key(42, pixel, s), bounce, d);
                    ASSERT_EQ(sample_uniform(SamplerKind::Independent, stream_key(42, pixel), s, bounce, d), want);
                }
}

TEST(Sobol, TheIndexShuffleMapsAlignedBlocksOntoAlignedBlocks) {
    // a nested scramble of the index: the 2^m indices of an aligned block go to the 2^m of
    // one aligned block (itself from kShuffleLevels on), and the order within it changes
    for (uint32_t seed : {0u, 7u, 0xdeadbeefu})
        for (int m : {0, 1, 3, 6, 12, 14})
            for (uint32_t block : {0u, 1u, 9u, 1000u}) {
                const uint32_t n = 1u << m, first = block * n;
                const uint32_t high = sobol::shuffle_index(first, seed) >> m;
                std::vector<int> seen(n, 0);
                for (uint32_t i = first; i < first + n; ++i) {
                    const uint32_t j = sobol::shuffle_index(i, seed);
                    ASSERT_EQ(j >> m, high) << "m " << m << " block " << block;
                    ++seen[j & (n - 1)];
                }
                for (int c : seen) ASSERT_EQ(c, 1);
                if (m >= sobol::kShuffleLevels) {
                    EXPECT_EQ(high, block);
                }
            }
    int moved = 0;
    for (uint32_t i = 0; i < 256; ++i) moved += sobol::shuffle_index(i, 12345u) != i;
    EXPECT_GT(moved, 100);
}

TEST(SampleNumbers, UsesComeInPairsAndSinglesWithTheirOwnGroups) {
    // the pairs draw the (0, 2)-sequence's two dimensions, the single uses its first; every
    // (bounce, group) has its own id
    EXPECT_EQ(sobol_group(0, kDimPixelX).component, 0);
    EXPECT_EQ(sobol_group(0, kDimPixelY).component, 1);
    EXPECT_EQ(sobol_group(0, kDimPixelY).id, sobol_group(0, kDimPixelX).id);
    EXPECT_EQ(sobol_group(3, kDimLightV).id, sobol_group(3, kDimLightU).id);
    EXPECT_EQ(sobol_group(3, kDimBsdfV).id, sobol_group(3, kDimBsdfU).id);
    std::vector<uint32_t> ids;
    for (int bounce = 0; bounce < 40; ++bounce)
        for (RandomDim d : {kDimPixelX, kDimLensU, kDimLightPick, kDimLightU, kDimBsdfPick, kDimBsdfU, kDimRoulette}) {
            EXPECT_EQ(sobol_group(bounce, d).component, 0);
            for (uint32_t id : ids) ASSERT_NE(id, sobol_group(bounce, d).id) << "bounce " << bounce << " use " << d;
            ids.push_back(sobol_group(bounce, d).id);
        }
}

// The top bits of a number in [0, 1), as sample_uniform's 24 bits at the top of a uint32.
uint32_t bits_of(float u) { return static_cast<uint32_t>(u * 16777216.0f) << 8; }

TEST(SampleNumbers, SobolNumbersAreAPixelsStratifiedSequence) {
    // a pixel's first 64 samples, and its 64 after them: every pair of every bounce (deep
    // ones too) a (0, 6, 2)-net, every use stratified in 64 intervals; another pixel
    // (stream) draws other numbers
    const uint32_t key = stream_key(7, 1234), other = stream_key(7, 1235);
    for (uint32_t first : {0u, 64u})
        for (int bounce : {0, 1, 2, 17, 40}) {
            for (RandomDim d : {kDimLensU, kDimLightPick, kDimLightV, kDimBsdfPick, kDimBsdfU, kDimRoulette}) {
                std::vector<int> count(64, 0);
                int same = 0;
                for (uint32_t i = first; i < first + 64; ++i) {
                    const float u = sample_uniform(SamplerKind::Sobol, key, i, bounce, d);
                    ASSERT_GE(u, 0.0f);
                    ASSERT_LT(u, 1.0f);
                    ++count[static_cast<int>(u * 64)];
                    same += u == sample_uniform(SamplerKind::Sobol, other, i, bounce, d);
                }
                for (int c : count) ASSERT_EQ(c, 1) << "bounce " << bounce << " use " << d;
                EXPECT_LT(same, 4);
            }
            for (RandomDim d : {kDimPixelX, kDimLensU, kDimLightU, kDimBsdfU}) {
                std::vector<uint32_t> x, y;
                for (uint32_t i = first; i < first + 64; ++i) {
                    x.push_back(bits_of(sample_uniform(SamplerKind::Sobol, key, i, bounce, d)));
                    y.push_back(bits_of(sample_uniform(SamplerKind::Sobol, key, i, bounce, static_cast<RandomDim>(d + 1))));
                }
                EXPECT_TRUE(is_02_net(x, y, 6)) << "bounce " << bounce << " use " << d << " first " << first;
            }
        }
}

TEST(SampleNumbers, TheGroupsArePairedAtRandom) {
    // two groups' numbers of a pixel's samples: each group shuffles the index its own way,
    // so the mean c of (u - 1/2)(v - 1/2) over a pixel's n samples is near that of a random
    // pairing, 1/144 / n in square (up to twice that: a nested shuffle pairs two samples
    // that share all but their last index bit, in opposite halves of [0, 1), with two such
    // of the other group); one order for both (the scrambles of the values alone) would
    // keep the top bits of u and v equal or opposite, c^2 near 1/256, 144 n / 256 times the
    // random pairing's. Every two groups of bounce 0, and each use of bounce 0 against
    // itself at bounce 1.
    struct Use {
        int bounce;
        RandomDim d;
    };
    const RandomDim uses[] = {kDimPixelX, kDimLensU, kDimLightPick, kDimLightU, kDimBsdfPick, kDimBsdfU, kDimRoulette};
    std::vector<std::pair<Use, Use>> pairs;
    for (RandomDim a : uses)
        for (RandomDim b : uses)
            if (a < b) pairs.push_back({{0, a}, {0, b}});
    for (RandomDim a : uses)
        if (a >= kDimLightPick) pairs.push_back({{0, a}, {1, a}});
    const int pixels = 64, n = 256;
    for (const auto& [a, b] : pairs) {
        double c2 = 0;
        for (uint32_t p = 0; p < pixels; ++p) {
            const uint32_t key = stream_key(3, p);
            double c = 0;
            for (uint32_t i = 0; i < n; ++i)
                c += (sample_uniform(SamplerKind::Sobol, key, i, a.bounce, a.d) - 0.5) *
                     (sample_uniform(SamplerKind::Sobol, key, i, b.bounce, b.d) - 0.5);
            c2 += (c / n) * (c / n) / pixels;
        }
        EXPECT_LT(c2 * 144.0 * n, 3.5) << "uses " << a.d << " and " << b.d << " (bounce " << b.bounce << ")";
        EXPECT_GT(c2 * 144.0 * n, 0.3) << "uses " << a.d << " and " << b.d << " (bounce " << b.bounce << ")";
    }
}

}  // namespace
