// The fixture of the lane tests: a width the CPU cannot run is skipped in SetUp, which is
// compiled without that width's flags (lane_width_fixture.cpp). The check cannot sit in the
// test body: a body compiled with -mavx512f may use AVX-512 instructions before its first
// line (a sanitizer's stack poisoning does), which is an illegal instruction on a CPU without it.
#pragma once

#include <gtest/gtest.h>

namespace patina::test {

class LaneWidthFixture : public ::testing::Test {
protected:
    explicit LaneWidthFixture(int width) : m_width(width) {}
    void SetUp() override;

private:
    int m_width;
};

template <int W>
class LaneWidth : public LaneWidthFixture {
protected:
    LaneWidth() : LaneWidthFixture(W) {}
};

}  // namespace patina::test
