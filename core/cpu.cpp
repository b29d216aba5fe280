#include "cpu.h"

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace patina {

const CpuFeatures& cpu_features() {
    static const CpuFeatures features = [] {
        CpuFeatures f;
#if defined(__x86_64__) || defined(__i386__)
        __builtin_cpu_init();
        f.sse41 = __builtin_cpu_supports("sse4.1");
        // libgcc checks XGETBV for the AVX state before reporting avx2 / fma.
        f.avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
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
        default: return false;
    }
}

static int width_from_env() {
    const char* env = std::getenv("PATINA_SIMD");
    if (!env || !*env) return 0;
    const std::string s(env);
    int w = 0;
    // The same numbers as --simd and width= (1, 4, 8), or the instruction-set names.
    if (s == "1" || s == "scalar") w = 1;
    else if (s == "4" || s == "sse4") w = 4;
    else if (s == "8" || s == "avx2") w = 8;
    else throw std::invalid_argument("PATINA_SIMD=" + s + ": expected 1, 4 or 8 (or scalar, sse4, avx2)");
    if (!width_supported(w)) throw std::invalid_argument("PATINA_SIMD=" + s + ": this CPU cannot run that path");
    return w;
}

int default_width() {
    const int forced = width_from_env();
    if (forced) return forced;
    if (width_supported(8)) return 8;
    if (width_supported(4)) return 4;
    return 1;
}

int resolve_width(int requested) {
    if (requested == 0) return default_width();
    if (requested != 1 && requested != 4 && requested != 8)
        throw std::invalid_argument("width=" + std::to_string(requested) + ": expected 1, 4 or 8");
    if (!width_supported(requested))
        throw std::invalid_argument("width=" + std::to_string(requested) + ": this CPU cannot run that path");
    return requested;
}

}  // namespace patina
