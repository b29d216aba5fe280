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
        std::vector<float> model(3 * kChunk);
        double sum = 0;
        for (size_t i = begin; i < end; i += kChunk) {
            const size_t m = std::min(kChunk, end - i);
            k.eval_lambert_ggx(p, s.wi + 3 * i, s.wo + 3 * i, model.data(), m);
            const float* meas = s.measured + 3 * i;
            const float* w = s.weight + i;
            if (kind == LossKind::CosineL2) {
                for (size_t j = 0; j < 3 * m; ++j) {
                    const double d = (double(model[j]) - meas[j]) * w[j / 3];
                    sum += d * d;
                }
            } else {
                for (size_t j = 0; j < 3 * m; ++j) {
                    const double d = std::log1p(double(model[j]) * w[j / 3]) - std::log1p(double(meas[j]) * w[j / 3]);
                    sum += d * d;
                }
            }
        }
        std::lock_guard<std::mutex> g(lock);
        total += sum;
    });
    return s.n ? total / (3.0 * double(s.n)) : 0.0;
}

}  // namespace patina
