// A tabulated BRDF on a tensor grid with irregular, strictly increasing axes.
//
// Axes are in radians, in the order the parametrization names them:
//   isotropic    (theta_i, theta_o, phi_d)           phi_d = |phi_o - phi_i| in [0, pi]
//   anisotropic  (theta_i, phi_i, theta_o, phi_o)    phi in [0, 2 pi)
//   halfdiff     (theta_h, theta_d, phi_d)           Rusinkiewicz; phi_d in [0, pi) with
//                                                    reciprocity (MERL), [0, pi/2] with mirror
// Values are stored row-major over the grid (last axis fastest) with the channels
// innermost: values[point * channels + c]. Missing measurements are marked in
// `valid` (one byte per grid point; empty = all measured) and hold 0 in `values`.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace patina {

enum class Parametrization : uint32_t { Isotropic = 0, Anisotropic = 1, HalfDiff = 2 };
enum class ChannelKind : uint32_t { Mono = 0, RGB = 1, XYZ = 2, Spectral = 3 };

// Symmetries a table declares, applied by the evaluator before the lookup.
enum SymmetryFlags : uint32_t {
    kSymReciprocity = 1u << 0,  // halfdiff: phi_d folded into [0, pi); iso/aniso: (i, o) swapped so theta_i <= theta_o
    kSymPhiMirror = 1u << 1,    // halfdiff: phi_d folded into [0, pi/2] (phi_d -> pi - phi_d)
};

constexpr int kMaxAxes = 4;

int axis_count(Parametrization p);
const char* parametrization_name(Parametrization p);
const char* channel_kind_name(ChannelKind k);
const char* axis_name(Parametrization p, int axis);

struct Table {
    Parametrization parametrization = Parametrization::Isotropic;
    ChannelKind channel_kind = ChannelKind::RGB;
    uint32_t symmetry = 0;
    std::vector<std::vector<float>> axes;
    int channels = 0;
    std::vector<float> wavelengths;  // nm, one per channel when spectral
    std::vector<float> values;
    std::vector<uint8_t> valid;
    std::string units = "1/sr";
    std::string provenance;

    size_t point_count() const;  // product of the axis lengths
    size_t missing_count() const;
    // Throws std::invalid_argument naming the first problem: axis counts and
    // monotonicity, sizes, non-finite values, channel/wavelength consistency.
    void check() const;
};

// What the SIMD kernels read: plain pointers and strides, no ownership.
struct TableView {
    Parametrization parametrization;
    uint32_t symmetry;
    int dims;
    int channels;
    const float* knots[kMaxAxes];
    const float* inv_widths[kMaxAxes];  // 1 / (knots[i + 1] - knots[i]), one per cell
    int lengths[kMaxAxes];
    int32_t strides[kMaxAxes];  // in grid points
    const float* values;    // followed by at least kValuePadding readable floats
    const float* coverage;  // 1 where measured, 0 where missing; nullptr when nothing is missing
};

// Floats of slack after the values: the RGB kernels load 4 floats per 3-float row.
constexpr int kValuePadding = 4;

// The arrays the kernels read, derived from a checked table and kept alive with the view:
// a padded copy of the values, the coverage (when points are missing), inverse cell widths.
struct PreparedTable {
    TableView view;
    std::vector<float> values;
    std::vector<float> coverage;
    std::vector<float> inv_widths[kMaxAxes];
};

PreparedTable prepare(const Table& table);

}  // namespace patina
