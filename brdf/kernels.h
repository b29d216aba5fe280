// Run-time dispatch to the kernels compiled for each SIMD width.
//
// kernels_w1.cpp, kernels_w4.cpp (-msse4.1) and kernels_w8.cpp (-mavx2 -mfma)
// each compile kernels_impl.h for their width; kernels_for(width) picks one.
// All entry points work on arrays of any length (the tail goes through the same
// width-N code, padded).
#pragma once

#include <cstddef>
#include <cstdint>

#include "brdf/table.h"

namespace patina {

enum class MathOp : int { Acos, Asin, Atan, Atan2, Sqrt, Rcp, Rsqrt, LibcAcos, LibcAtan2 };

struct Kernels {
    int width;
    // out[i] = op(a[i]) or op(a[i], b[i]) (atan2: a = y, b = x).
    void (*math)(MathOp op, const float* a, const float* b, float* out, size_t n);
    // cells[i] = coherent_search(knots, count, x[i]), with the masked split walk (Patina's)
    // or the thesis's sequential one.
    void (*search)(const float* knots, int count, const float* x, int32_t* cells, size_t n);
    void (*search_thesis)(const float* knots, int count, const float* x, int32_t* cells, size_t n);
    // Evaluates pairs [begin, end) of (n, 3) arrays into out (n, channels).
    void (*eval)(const TableView& t, const float* wi, const float* wo, float* out, size_t begin, size_t end);
    // Width 1 only (nullptr otherwise): the same evaluator with the C library's acos and
    // atan2, the naive scalar baseline benchmarks also report against.
    void (*eval_libm)(const TableView& t, const float* wi, const float* wo, float* out, size_t begin, size_t end);
};

const Kernels& kernels_w1();
const Kernels& kernels_w4();
const Kernels& kernels_w8();
const Kernels& kernels_w16();

// width 0 = default (PATINA_SIMD or the widest the CPU runs); throws std::invalid_argument otherwise.
const Kernels& kernels_for(int width);

// Evaluates n pairs, split over `threads` threads (0 = all) when the batch is large.
// libm_trig selects the width-1 evaluator with the C library's trigonometry (a baseline).
void eval_batch(const TableView& t, const float* wi, const float* wo, float* out, size_t n, int width, int threads,
                bool libm_trig = false);

}  // namespace patina
