// The sampler's numbers for N paths at once (render/samplers/sample_numbers.h's lanes version), lane
// by lane against the scalar one: bit-identical for both samplers, every use, bounces past
// the Sobol table included. Included after tests/cpp/core/simd/simd_lane_tests.h (its fixture) by
// test_simd_w{4,8,16}.cpp.
#pragma once

#include <cstdint>
#include <random>

#include "render/samplers/sample_numbers.h"

LANE_TEST(SampleNumbersMatchScalar) {
    std::mt19937 rng(5);
    for (const patina::SamplerKind kind : {patina::SamplerKind::Sobol, patina::SamplerKind::Independent})
        for (int trial = 0; trial < 64; ++trial) {
            int32_t keys[N], index[N];
            uint32_t all = 0;
            for (int j = 0; j < N; ++j) {
                keys[j] = static_cast<int32_t>(rng());
                // small indices (a pixel's first samples) and any 32-bit one
                index[j] = static_cast<int32_t>(trial % 2 ? rng() : rng() % 300);
                all |= static_cast<uint32_t>(index[j]);
            }
            for (int bounce = 0; bounce < 20; ++bounce)
                for (int d = 0; d <= static_cast<int>(patina::kDimRoulette); ++d) {
                    const auto use = static_cast<patina::RandomDim>(d);
                    const F got = patina::sample_uniform_lanes(kind, load_n<N>(keys), load_n<N>(index),
                                                               patina::bit_length(all), bounce, use);
                    for (int j = 0; j < N; ++j) {
                        const float want = patina::sample_uniform(kind, static_cast<uint32_t>(keys[j]),
                                                                  static_cast<uint32_t>(index[j]), bounce, use);
                        ASSERT_TRUE(same_float(patina::lane(got, j), want))
                            << "lane " << j << " bounce " << bounce << " use " << d << " trial " << trial;
                    }
                }
        }
}
