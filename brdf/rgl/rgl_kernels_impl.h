// The body of rgl_kernels_w{1,4,8,16}.cpp: the RGL evaluator, pdf and sampler over arrays,
// for PATINA_KERNEL_WIDTH. Each range keeps its search hints from block to block: coherent
// blocks start their incident-angle searches where the previous one ended.
#pragma once

#include "brdf/rgl/rgl_eval.h"
#include "brdf/rgl/rgl_kernels.h"
#include "brdf/rgl/rgl_sample.h"
#include "core/simd/kernel_width.h"

PATINA_BEGIN_TARGET
namespace {
using namespace kernel_width;

void rgl_eval_kernel(const RglView& v, const float* wi, const float* wo, float* out, size_t begin, size_t end) {
    enter_kernel();
    RglHints hints;
    const float *first_wi = wi + 3 * begin, *first_wo = wo + 3 * begin;
    float* first_out = out + kRglChannels * begin;
    for_blocks(end - begin, [&](size_t i, int lanes) {
        F rgb[kRglChannels];
        rgl_eval_block<N>(v, load_rows(first_wi, i, lanes), load_rows(first_wo, i, lanes), hints, rgb);
        store_rows(first_out, i, lanes, rgb[0], rgb[1], rgb[2]);
    });
}

void rgl_pdf_kernel(const RglView& v, const float* wi, const float* wo, float* pdf, size_t begin, size_t end) {
    enter_kernel();
    RglHints hints;
    const float *first_wi = wi + 3 * begin, *first_wo = wo + 3 * begin;
    for_blocks(end - begin, [&](size_t i, int lanes) {
        const F p = rgl_pdf_block<N>(v, load_rows(first_wi, i, lanes), load_rows(first_wo, i, lanes), hints);
        store_lanes(pdf + begin, i, lanes, p);
    });
}

void rgl_sample_kernel(const RglView& v, const float* wi, const float* u1, const float* u2, float* wo, float* pdf,
                       size_t begin, size_t end) {
    enter_kernel();
    RglHints hints;
    for_blocks(end - begin, [&](size_t i, int lanes) {
        const RglSampled<N> s =
            rgl_sample_block<N>(v, load_rows(wi + 3 * begin, i, lanes), load_lanes(u1 + begin, i, lanes),
                                load_lanes(u2 + begin, i, lanes), hints);
        store_rows(wo + 3 * begin, i, lanes, s.wo);
        store_lanes(pdf + begin, i, lanes, s.pdf);
    });
}

}  // namespace
PATINA_END_TARGET
