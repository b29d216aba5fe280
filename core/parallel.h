// Splitting a batch over threads.
#pragma once

#include <cstddef>
#include <functional>

namespace patina {

// Number of worker threads to use when the caller passes 0: all hardware threads.
int default_thread_count();

// Calls body(begin, end) on disjoint chunks covering [0, n). Chunk boundaries are
// multiples of `grain` (so SIMD kernels see whole vectors except in the last
// chunk). Runs inline when n is small or threads == 1. Exceptions from the body
// are rethrown in the caller after all threads have joined.
void parallel_for(size_t n, size_t grain, int threads, const std::function<void(size_t, size_t)>& body);

}  // namespace patina
