// The corners' comparisons in SIMD lanes (render/antialiasing/signal_lanes.h) decide every
// pair exactly as the scalar aa_differs does, lane by lane, on signals of every kind:
// misses, NaN and infinite values, normals a little longer than 1 (the clamp's cases),
// zeros, negative colours, and a row length that leaves a partial vector at the end.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "render/antialiasing/adaptive_sampler.h"
#include "render/antialiasing/signal_lanes.h"
#include "render/samplers/rng.h"

namespace {

struct RandomSignals {
    uint32_t h = 777;
    float next() {
        h = patina::hash_u32(h);
        return static_cast<float>(h >> 8) / 16777216.0f;
    }
    // a value of a signal's channel: mostly ordinary, sometimes zero, negative, inf or NaN
    float value(float scale) {
        const float pick = next();
        if (pick < 0.05f) return 0.0f;
        if (pick < 0.08f) return std::numeric_limits<float>::infinity();
        if (pick < 0.10f) return std::nanf("");
        if (pick < 0.15f) return -scale * next();
        return scale * next();
    }
    patina::PathResult result() {
        patina::PathResult r{};
        for (float& c : r.rgb) c = value(10);
        // unit normals (or 1.01 long: dot products beyond [-1, 1]), sometimes broken
        const float nz = 2 * next() - 1, length = next() < 0.2f ? 1.01f : 1.0f;
        r.normal[0] = length * std::sqrt(1 - nz * nz);
        r.normal[1] = 0;
        r.normal[2] = next() < 0.02f ? std::nanf("") : length * nz;
        r.depth = value(5);
        return r;
    }
};

patina::AaSignal signal_of(const patina::PathResult& r) {
    return {{r.rgb[0], r.rgb[1], r.rgb[2]}, {r.normal[0], r.normal[1], r.normal[2]}, r.depth};
}

}  // namespace

TEST(AaSignalLanes, EveryLaneDecidesAsTheScalarComparison) {
    RandomSignals random;
    const size_t n = 1003;  // not a multiple of any vector width
    std::vector<patina::PathResult> results(n);
    patina::AaSignalLanes lanes;
    lanes.resize(n);
    for (size_t q = 0; q < n; ++q) {
        results[q] = random.result();
        if (q % 5 == 0 && q > 0) results[q] = results[q - 1];  // equal neighbours too
        lanes.set(q, results[q]);
    }
    int differing = 0;
    for (const float t : {0.0f, 0.05f, 0.15f, 0.5f, 1.0f})
        for (const size_t offset : {size_t{1}, size_t{33}}) {
            const size_t count = n - offset;
            std::vector<uint8_t> out(count, 7);
            patina::aa_differs_lanes(lanes, 0, offset, count, t, out.data());
            for (size_t k = 0; k < count; ++k) {
                const bool scalar = patina::aa_differs(signal_of(results[k]), signal_of(results[k + offset]), t);
                ASSERT_EQ(out[k], scalar ? 1 : 0) << "lane " << k << " threshold " << t << " offset " << offset;
                differing += scalar;
            }
        }
    EXPECT_GT(differing, 1000);  // both outcomes are exercised
    EXPECT_LT(differing, 9000);
}
