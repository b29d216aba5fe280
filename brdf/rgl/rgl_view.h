// The arrays of an RGL .bsdf material (Dupuy & Jakob 2018) as the native evaluator reads them.
//
// Python's reader (python/patina/table/formats/rgl_brdf.py) checks the file, converts spectra
// to linear sRGB and normalises the two warps (marginal and conditional CDFs, rgl_warp.py);
// the kernels read those arrays as they are, in float32. Every 2-D grid is (height = phi rows,
// width = theta columns), C order; the warps and the values have one grid per incident-angle
// pair (phi_i, theta_i), the values one per (phi_i, theta_i, channel).
#pragma once

namespace patina {

constexpr int kRglChannels = 3;  // linear sRGB: spectral files are converted by the reader

// A bilinear grid over [0, 1]^2: x along the width, y along the height.
struct RglGridView {
    const float* data = nullptr;
    int height = 0, width = 0;
};

// A density with its CDFs, one grid per incident-angle pair: data (slices, height * width)
// normalised, marginal (slices, height) over the rows, conditional (slices, height * width)
// along each row, both scaled by the same normalisation (rgl_warp.Interpolant2D, warp=True).
struct RglWarpView {
    const float* data = nullptr;
    const float* marginal = nullptr;
    const float* conditional = nullptr;
    int height = 0, width = 0;
};

struct RglView {
    const float* theta_i = nullptr;  // the incident-angle parameters, increasing
    const float* phi_i = nullptr;
    int theta_count = 0, phi_count = 0;
    RglGridView ndf, sigma;
    RglWarpView vndf, luminance;
    RglGridView values;  // one grid per (phi_i, theta_i, channel): kRglChannels channels
    bool isotropic = true;  // phi_m is taken relative to phi_i
    bool jacobian = true;   // values times ndf / (4 sigma)
    int reduction = 1;      // phi_i covers 360 / reduction degrees: 1, 2 or 4
};

}  // namespace patina
