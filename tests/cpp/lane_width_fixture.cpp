// Compiled with the baseline flags only: see lane_width_fixture.h.
#include "tests/cpp/lane_width_fixture.h"

#include "core/cpu.h"

namespace patina::test {

void LaneWidthFixture::SetUp() {
    if (!width_supported(m_width)) GTEST_SKIP() << "CPU lacks width " << m_width;
}

}  // namespace patina::test
