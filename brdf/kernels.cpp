#include "brdf/kernels.h"

#include "core/parallel.h"
#include "core/width_dispatch.h"

namespace patina {

const Kernels& kernels_for(int width) {
    return kernels_for_width(width, kernels_w1, kernels_w4, kernels_w8, kernels_w16);
}

void eval_batch(const TableView& t, const float* wi, const float* wo, float* out, size_t n, int width, int threads,
                bool libm_trig) {
    const Kernels& k = libm_trig ? kernels_w1() : kernels_for(width);
    const auto kernel = libm_trig ? k.eval_libm : k.eval;
    parallel_for(n, 64, threads, [&](size_t begin, size_t end) { kernel(t, wi, wo, out, begin, end); });
}

}  // namespace patina
