// The scalar path (width 1): fast-math error bounds and special values against double.
#define PATINA_TEST_WIDTH 1
#include "tests/cpp/core/simd/simd_lane_tests.h"
