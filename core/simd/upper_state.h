// Clearing the upper halves of the vector registers before legacy-SSE code runs.
//
// On recent Intel CPUs, non-VEX SSE instructions executed while the upper bits of
// the YMM/ZMM registers are "dirty" (left so by some AVX code elsewhere in the
// process: the C library, numpy) pay a merge penalty on every instruction. The
// scalar and 4-wide kernels are non-VEX (they must run on pre-AVX CPUs), so each
// kernel entry point calls this first. Measured: the 4-wide coherent search went
// from 155 to 230 M/s on the development machine.
#pragma once

namespace patina {

// Executes VZEROUPPER when the CPU has AVX; does nothing otherwise.
void clear_upper_state();

}  // namespace patina
