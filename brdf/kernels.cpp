#include "brdf/kernels.h"

#include "core/cpu.h"
#include "core/parallel.h"

namespace patina {

const Kernels& kernels_for(int width) {
    switch (resolve_width(width)) {
        case 8: return kernels_w8();
        case 4: return kernels_w4();
        default: return kernels_w1();
    }
}

void eval_batch(const TableView& t, const float* wi, const float* wo, float* out, size_t n, int width, int threads,
                bool libm_trig) {
    const Kernels& k = libm_trig ? kernels_w1() : kernels_for(width);
    const auto kernel = libm_trig ? k.eval_libm : k.eval;
    parallel_for(n, 64, threads, [&](size_t begin, size_t end) { kernel(t, wi, wo, out, begin, end); });
}

}  // namespace patina
