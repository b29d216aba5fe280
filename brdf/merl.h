// MERL BRDF database .binary files (Matusik et al. 2003), read exactly as the
// reference reader lays them out:
//   three int32 dims (90, 90, 180), then 3 x 90 x 90 x 180 float64 values: all
//   red, then all green, then all blue; index phi_d + 180 theta_d + 180*90 theta_h;
//   scales 1/1500, 1.15/1500, 1.66/1500.
// Patina holds the grid as irregular knots: theta_h bin i at i^2/90 degrees (the
// square-root axis), theta_d bin j at j degrees, phi_d bin k at k degrees, plus a
// knot at 180 degrees that repeats phi_d = 0 (phi_d has period pi by reciprocity),
// so interpolation wraps across the seam. Negative values mark missing
// measurements: such points are masked (not interpolated as data) and counted.
#pragma once

#include <string>

#include "brdf/table.h"

namespace patina {

constexpr int kMerlThetaH = 90, kMerlThetaD = 90, kMerlPhiD = 180;

// Throws FormatError for a short, long, mis-dimensioned or non-finite file.
Table read_merl(const std::string& path);

}  // namespace patina
