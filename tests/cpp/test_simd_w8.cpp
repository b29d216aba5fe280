// SIMD ops at width 8 (compiled with -mavx2 -mfma), lane by lane against width 1.
#define PATINA_TEST_WIDTH 8
#include "simd_lane_tests.h"
#include "sample_numbers_lane_tests.h"
