// A 2-D table on an irregular tensor grid: strictly increasing knots along x (nx) and y
// (ny), values row-major (values[ix * ny + iy]). What a goniometric light's candela table is.
#pragma once

namespace patina {

struct Grid2View {
    const float* x;
    int nx;
    const float* y;
    int ny;
    const float* values;
};

}  // namespace patina
