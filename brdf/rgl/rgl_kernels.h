// Run-time dispatch to the RGL evaluator compiled for each SIMD width (rgl_kernels_w*.cpp
// compile rgl_kernels_impl.h with their width's flags, as brdf/kernels.h does for tables).
#pragma once

#include <cstddef>

#include "brdf/rgl/rgl_view.h"

namespace patina {

struct RglKernels {
    int width;
    // Pairs [begin, end) of (n, 3) arrays wi, wo: out (n, 3) linear sRGB f, or pdf (n,) of wo.
    void (*eval)(const RglView& v, const float* wi, const float* wo, float* out, size_t begin, size_t end);
    void (*pdf)(const RglView& v, const float* wi, const float* wo, float* pdf, size_t begin, size_t end);
    // Rows [begin, end): wo (n, 3) and its pdf (n,) sampled for wi (n, 3) from uniforms u1, u2 (n,).
    void (*sample)(const RglView& v, const float* wi, const float* u1, const float* u2, float* wo, float* pdf,
                   size_t begin, size_t end);
};

const RglKernels& rgl_kernels_w1();
const RglKernels& rgl_kernels_w4();
const RglKernels& rgl_kernels_w8();
const RglKernels& rgl_kernels_w16();

// width 0 = default; throws std::invalid_argument for a width the CPU cannot run.
const RglKernels& rgl_kernels_for(int width);

// n pairs split over `threads` threads (0 = all) when the batch is large.
void rgl_eval_batch(const RglView& v, const float* wi, const float* wo, float* out, size_t n, int width, int threads);
void rgl_pdf_batch(const RglView& v, const float* wi, const float* wo, float* pdf, size_t n, int width, int threads);
void rgl_sample_batch(const RglView& v, const float* wi, const float* u1, const float* u2, float* wo, float* pdf,
                      size_t n, int width, int threads);

}  // namespace patina
