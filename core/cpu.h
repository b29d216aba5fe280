// Which SIMD widths this CPU can run, and which one to use.
//
// PATINA_SIMD=1|4|8|16 (or scalar|sse4|avx2|avx512) in the environment forces a path (an
// error if the CPU cannot run it); otherwise the widest supported path is used: width 16
// on CPUs with AVX-512 (F, VL, DQ, BW) and the OS's ZMM state, width 8 without it.
#pragma once

namespace patina {

struct CpuFeatures {
    bool sse41 = false;
    bool avx2 = false;    // AVX2 and FMA, with OS support for the YMM state
    bool avx512 = false;  // AVX-512 F, VL, DQ and BW (and AVX2 + FMA), with OS support for the ZMM state
};

const CpuFeatures& cpu_features();

// True if kernels of this width (1, 4, 8 or 16) can run here.
bool width_supported(int width);

// The width to use when the caller did not ask for one: PATINA_SIMD or the widest.
int default_width();

// 0 means default_width(); otherwise checks the width is 1, 4, 8 or 16 and supported,
// throwing std::invalid_argument with a clear message if not.
int resolve_width(int requested);

}  // namespace patina
