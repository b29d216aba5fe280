#include "brdf/rgl/rgl_kernels.h"

#include "core/parallel.h"
#include "core/width_dispatch.h"

namespace patina {

const RglKernels& rgl_kernels_for(int width) {
    return kernels_for_width(width, rgl_kernels_w1, rgl_kernels_w4, rgl_kernels_w8, rgl_kernels_w16);
}

void rgl_eval_batch(const RglView& v, const float* wi, const float* wo, float* out, size_t n, int width, int threads) {
    const auto kernel = rgl_kernels_for(width).eval;
    parallel_for(n, 64, threads, [&](size_t begin, size_t end) { kernel(v, wi, wo, out, begin, end); });
}

void rgl_pdf_batch(const RglView& v, const float* wi, const float* wo, float* pdf, size_t n, int width, int threads) {
    const auto kernel = rgl_kernels_for(width).pdf;
    parallel_for(n, 64, threads, [&](size_t begin, size_t end) { kernel(v, wi, wo, pdf, begin, end); });
}

void rgl_sample_batch(const RglView& v, const float* wi, const float* u1, const float* u2, float* wo, float* pdf,
                      size_t n, int width, int threads) {
    const auto kernel = rgl_kernels_for(width).sample;
    parallel_for(n, 64, threads, [&](size_t begin, size_t end) { kernel(v, wi, u1, u2, wo, pdf, begin, end); });
}

}  // namespace patina
