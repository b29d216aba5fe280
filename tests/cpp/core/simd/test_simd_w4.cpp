// SIMD ops at width 4 (compiled with -msse4.1), lane by lane against width 1.
#define PATINA_TEST_WIDTH 4
#include "tests/cpp/core/simd/simd_lane_tests.h"
#include "tests/cpp/render/samplers/sample_numbers_lane_tests.h"
#include "tests/cpp/render/materials/rgl_material_lane_tests.h"
