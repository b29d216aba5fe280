// SIMD ops at width 4 (compiled with -msse4.1), lane by lane against width 1.
#define PATINA_TEST_WIDTH 4
#include "simd_lane_tests.h"
#include "sample_numbers_lane_tests.h"
