#include "cpu.h"

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#endif

#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace patina {

#if defined(__x86_64__) || defined(__i386__)
// AVX-512 F, VL, DQ and BW from CPUID leaf 7, and the OS's promise (XCR0, read with XGETBV,
// which OSXSAVE allows) to save the SSE, AVX, opmask, ZMM0-15 upper halves and ZMM16-31
// state on a context switch: without it the first AVX-512 instruction faults, whatever
// CPUID says. Read here rather than trusted to the compiler's runtime, so the check is
// the one the dispatcher's comment describes. The xgetbv is an asm statement, so no
// AVX-512 (or AVX) instruction is in this file.
static bool cpu_has_avx512() {
    unsigned a = 0, b = 0, c = 0, d = 0;
    if (!__get_cpuid(1, &a, &b, &c, &d)) return false;
    if (!(c & (1u << 27))) return false;  // OSXSAVE
    uint32_t xcr0_lo = 0, xcr0_hi = 0;
    __asm__ volatile("xgetbv" : "=a"(xcr0_lo), "=d"(xcr0_hi) : "c"(0));
    (void)xcr0_hi;  // the state components above bit 31 are not needed
    const uint32_t sse_avx_zmm = (1u << 1) | (1u << 2) | (1u << 5) | (1u << 6) | (1u << 7);
    if ((xcr0_lo & sse_avx_zmm) != sse_avx_zmm) return false;
    if (!__get_cpuid_count(7, 0, &a, &b, &c, &d)) return false;
    const unsigned f = 1u << 16, dq = 1u << 17, bw = 1u << 30, vl = 1u << 31;
    return (b & (f | dq | bw | vl)) == (f | dq | bw | vl);
}
#endif

const CpuFeatures& cpu_features() {
    static const CpuFeatures features = [] {
        CpuFeatures f;
#if defined(__x86_64__) || defined(__i386__)
        __builtin_cpu_init();
        f.sse41 = __builtin_cpu_supports("sse4.1");
        // libgcc checks XGETBV for the AVX state before reporting avx2 / fma.
        f.avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
        // The width-16 translation units are also compiled with -mavx2 -mfma.
        f.avx512 = f.avx2 && cpu_has_avx512();
#endif
        return f;
    }();
    return features;
}

bool width_supported(int width) {
    switch (width) {
        case 1: return true;
        case 4: return cpu_features().sse41;
        case 8: return cpu_features().avx2;
        case 16: return cpu_features().avx512;
        default: return false;
    }
}

static int width_from_env() {
    const char* env = std::getenv("PATINA_SIMD");
    if (!env || !*env) return 0;
    const std::string s(env);
    int w = 0;
    // The same numbers as --simd and width= (1, 4, 8, 16), or the instruction-set names.
    if (s == "1" || s == "scalar") w = 1;
    else if (s == "4" || s == "sse4") w = 4;
    else if (s == "8" || s == "avx2") w = 8;
    else if (s == "16" || s == "avx512") w = 16;
    else throw std::invalid_argument("PATINA_SIMD=" + s + ": expected 1, 4, 8 or 16 (or scalar, sse4, avx2, avx512)");
    if (!width_supported(w)) throw std::invalid_argument("PATINA_SIMD=" + s + ": this CPU cannot run that path");
    return w;
}

// Width 16 where the CPU has AVX-512: on the AVX-512 machine of December 2026 it renders the
// preview 1.2x faster than width 8 and evaluates MERL tables 1.4x faster, bit for bit the same
// (docs/performance.md, "Width 16 on a real AVX-512 CPU"). PATINA_SIMD=8 still forces 8.
int default_width() {
    const int forced = width_from_env();
    if (forced) return forced;
    if (width_supported(16)) return 16;
    if (width_supported(8)) return 8;
    if (width_supported(4)) return 4;
    return 1;
}

int resolve_width(int requested) {
    if (requested == 0) return default_width();
    if (requested != 1 && requested != 4 && requested != 8 && requested != 16)
        throw std::invalid_argument("width=" + std::to_string(requested) + ": expected 1, 4, 8 or 16");
    if (!width_supported(requested))
        throw std::invalid_argument("width=" + std::to_string(requested) + ": this CPU cannot run that path");
    return requested;
}

}  // namespace patina
