// SIMD ops at width 16 (compiled with PATINA_AVX512_FLAGS), lane by lane against width 1;
// skipped on a CPU without AVX-512 F/VL/DQ/BW (width_supported(16) false).
#define PATINA_TEST_WIDTH 16
#include "tests/cpp/core/simd/simd_lane_tests.h"
#include "tests/cpp/render/samplers/sample_numbers_lane_tests.h"
#include "tests/cpp/render/materials/rgl_material_lane_tests.h"
