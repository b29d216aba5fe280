// Fitting losses over a measured table's samples, evaluated with the SIMD lobe kernels
// and split over threads. A sample is a direction pair, its measured RGB value and a
// weight (cos(theta_i) cos(theta_o) for the losses below).
#pragma once

#include <cstddef>

#include "fit/lobe_kernels.h"

namespace patina {

enum class LossKind {
    // Ngan, Durand, Matusik 2005: squared difference of cosine-weighted values
    CosineL2,
    // Low et al. 2012: squared difference of log(1 + cosine-weighted value), which
    // balances the specular peak against the diffuse tail
    Log,
};

struct FitSamples {
    const float* wi;        // n x 3
    const float* wo;        // n x 3
    const float* measured;  // n x 3
    const float* weight;    // n
    size_t n;
};

// Mean loss over the samples and channels (double accumulation).
double mixture_loss(const MixtureParams& p, const FitSamples& s, LossKind kind, int width, int threads);

}  // namespace patina
