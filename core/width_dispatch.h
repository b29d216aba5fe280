// Choosing a kernel table by SIMD width. Each kernel family (table evaluation, analytic
// lobes, ray tracing, the integrator) is compiled once per width into its own translation
// units, each of which returns a table of function pointers (kernels_w4(), ...); these two
// helpers pick one of the four, at run time or at compile time, so no family repeats the
// switch over widths. Every family has every width: a width the CPU supports is one every
// family can run.
#pragma once

#include "core/cpu.h"

namespace patina {

template <class Table>
using KernelTableFn = const Table& (*)();

// The table for `width` (0: the default width; otherwise 1, 4, 8 or 16, checked by
// resolve_width, which throws std::invalid_argument for a width this CPU cannot run, so the
// width-16 table, whose code is AVX-512, is reached only when CPUID and the OS allow it).
template <class Table>
const Table& kernels_for_width(int width, KernelTableFn<Table> w1, KernelTableFn<Table> w4, KernelTableFn<Table> w8,
                               KernelTableFn<Table> w16) {
    switch (resolve_width(width)) {
        case 16: return w16();
        case 8: return w8();
        case 4: return w4();
        default: return w1();
    }
}

// The table compiled for width N, for kernels of one width calling another family's kernels
// of the same width (the integrator at width 4 tracing with the 4-wide packets).
template <int N, class Table>
const Table& kernels_at_width(KernelTableFn<Table> w1, KernelTableFn<Table> w4, KernelTableFn<Table> w8,
                              KernelTableFn<Table> w16) {
    static_assert(N == 1 || N == 4 || N == 8 || N == 16, "kernels are compiled for widths 1, 4, 8 and 16");
    if constexpr (N == 1) return w1();
    else if constexpr (N == 4) return w4();
    else if constexpr (N == 8) return w8();
    else return w16();
}

}  // namespace patina
