#include "fit/loss.h"

#include <algorithm>
#include <mutex>

#include "core/parallel.h"

namespace patina {

double mixture_loss(const MixtureParams& p, const FitSamples& s, LossKind kind, int width, int threads) {
    const LobeKernels& k = lobe_kernels_for(width);
    double total = 0;
    std::mutex lock;
    parallel_for(s.n, 1024, threads, [&](size_t begin, size_t end) {
        // in the SIMD kernel, blocks of rows; the block sums accumulate in double
        constexpr size_t kChunk = 2048;
        const bool log_space = kind == LossKind::Log;
        double sum = 0;
        for (size_t i = begin; i < end; i += kChunk) {
            const size_t m = std::min(kChunk, end - i);
            sum += k.loss_mixture(p, s.wi + 3 * i, s.wo + 3 * i, s.measured + 3 * i, s.weight + i, m, log_space);
        }
        std::lock_guard<std::mutex> g(lock);
        total += sum;
    });
    return s.n ? total / (3.0 * double(s.n)) : 0.0;
}

}  // namespace patina
