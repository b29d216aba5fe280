#include "fit/loss.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <vector>

#include "core/parallel.h"

namespace patina {

double lambert_ggx_loss(const LambertGgxParams& p, const FitSamples& s, LossKind kind, int width, int threads) {
    const LobeKernels& k = lobe_kernels_for(width);
    double total = 0;
    std::mutex lock;
    parallel_for(s.n, 1024, threads, [&](size_t begin, size_t end) {
        constexpr size_t kChunk = 2048;
        double sum = 0;
        if (kind == LossKind::CosineL2) {
            // entirely in the SIMD kernel; per-block sums accumulate in double
            for (size_t i = begin; i < end; i += kChunk) {
                const size_t m = std::min(kChunk, end - i);
                sum += k.cosine_l2_lambert_ggx(p, s.wi + 3 * i, s.wo + 3 * i, s.measured + 3 * i, s.weight + i, m);
            }
        } else {
            std::vector<float> model(3 * kChunk);
            for (size_t i = begin; i < end; i += kChunk) {
                const size_t m = std::min(kChunk, end - i);
                k.eval_lambert_ggx(p, s.wi + 3 * i, s.wo + 3 * i, model.data(), m);
                for (size_t r = 0; r < m; ++r) {
                    const double w = s.weight[i + r];
                    for (int c = 0; c < 3; ++c) {
                        const double d = std::log1p(double(model[3 * r + c]) * w) -
                                         std::log1p(double(s.measured[3 * (i + r) + c]) * w);
                        sum += d * d;
                    }
                }
            }
        }
        std::lock_guard<std::mutex> g(lock);
        total += sum;
    });
    return s.n ? total / (3.0 * double(s.n)) : 0.0;
}

}  // namespace patina
