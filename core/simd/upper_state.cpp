// The AVX instruction lives in a function with its own target attribute, run only after checking CPUID.
#include "core/simd/upper_state.h"

#include <immintrin.h>

#include "core/cpu.h"

namespace patina {

__attribute__((target("avx"))) static void vzeroupper() { _mm256_zeroupper(); }

void clear_upper_state() {
    static const bool has_avx = __builtin_cpu_supports("avx");
    if (has_avx) vzeroupper();
}

}  // namespace patina
