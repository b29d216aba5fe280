// The body of kernels_w{1,4,8}.cpp: defines kernels_wN() for PATINA_KERNEL_WIDTH.
#pragma once

#include <cmath>

#include "brdf/eval.h"
#include "brdf/kernels.h"
#include "brdf/search.h"
#include "core/simd/fastmath.h"
#include "core/simd/kernel_width.h"

PATINA_BEGIN_TARGET
namespace {
using namespace kernel_width;

template <class Op>
inline void map_unary(const float* a, float* out, size_t n, Op op) {
    size_t i = 0;
    for (; i + N <= n; i += N) store_n<N>(out + i, op(load_n<N>(a + i)));
    if (i < n) {
        float pa[N] = {}, po[N];
        for (size_t j = i; j < n; ++j) pa[j - i] = a[j];
        store_n<N>(po, op(load_n<N>(pa)));
        for (size_t j = i; j < n; ++j) out[j] = po[j - i];
    }
}

template <class Op>
inline void map_binary(const float* a, const float* b, float* out, size_t n, Op op) {
    size_t i = 0;
    for (; i + N <= n; i += N) store_n<N>(out + i, op(load_n<N>(a + i), load_n<N>(b + i)));
    if (i < n) {
        float pa[N] = {}, pb[N] = {}, po[N];
        for (size_t j = i; j < n; ++j) {
            pa[j - i] = a[j];
            pb[j - i] = b[j];
        }
        store_n<N>(po, op(load_n<N>(pa), load_n<N>(pb)));
        for (size_t j = i; j < n; ++j) out[j] = po[j - i];
    }
}

void math_kernel(MathOp op, const float* a, const float* b, float* out, size_t n) {
    enter_kernel();
    switch (op) {
        case MathOp::Acos: map_unary(a, out, n, [](F x) { return fast_acos(x); }); break;
        case MathOp::Asin: map_unary(a, out, n, [](F x) { return fast_asin(x); }); break;
        case MathOp::Atan: map_unary(a, out, n, [](F x) { return fast_atan(x); }); break;
        case MathOp::Atan2: map_binary(a, b, out, n, [](F y, F x) { return fast_atan2(y, x); }); break;
        case MathOp::Sqrt: map_unary(a, out, n, [](F x) { return fast_sqrt(x); }); break;
        case MathOp::Rcp: map_unary(a, out, n, [](F x) { return fast_rcp(x); }); break;
        case MathOp::Rsqrt: map_unary(a, out, n, [](F x) { return fast_rsqrt(x); }); break;
        // The C library, one value at a time: the baseline the fast versions are measured against.
        case MathOp::LibcAcos:
            for (size_t i = 0; i < n; ++i) out[i] = std::acos(a[i]);
            break;
        case MathOp::LibcAtan2:
            for (size_t i = 0; i < n; ++i) out[i] = std::atan2(a[i], b[i]);
            break;
    }
}

// The masked walk starts each block from where the previous one ended (SearchHint), as the
// evaluator does; the thesis's walk searches every block from the root, as the thesis did.
template <SplitWalk Walk>
PATINA_INLINE I search_block(const float* knots, int count, F x, SearchHint& hint) {
    if constexpr (Walk == SplitWalk::Masked)
        return coherent_search_cells<N, Walk>(knots, count, x, vbool<N>(true), hint).cell;
    else
        return coherent_search<N, Walk>(knots, count, x, vbool<N>(true));
}

template <SplitWalk Walk>
void search_kernel(const float* knots, int count, const float* x, int32_t* cells, size_t n) {
    enter_kernel();
    SearchHint hint;
    size_t i = 0;
    for (; i + N <= n; i += N) store_n<N>(cells + i, search_block<Walk>(knots, count, load_n<N>(x + i), hint));
    if (i < n) {
        float px[N] = {};
        int32_t pc[N];
        for (size_t j = i; j < n; ++j) px[j - i] = x[j];
        store_n<N>(pc, search_block<Walk>(knots, count, load_n<N>(px), hint));
        for (size_t j = i; j < n; ++j) cells[j] = pc[j - i];
    }
}

void eval_kernel(const TableView& t, const float* wi, const float* wo, float* out, size_t begin, size_t end) {
    enter_kernel();
    eval_range<N>(t, wi, wo, out, begin, end);
}

[[maybe_unused]] void eval_libm_kernel(const TableView& t, const float* wi, const float* wo, float* out, size_t begin,
                                       size_t end) {
    enter_kernel();
    eval_range<1, LibmTrig>(t, wi, wo, out, begin, end);
}

}  // namespace
PATINA_END_TARGET
