#include "brdf/merl.h"

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/binary_io.h"
#include "core/constants.h"
#include "core/errors.h"

namespace patina {

Table read_merl(const std::string& path) {
    BinaryReader in(path);
    int32_t dims[3];
    dims[0] = in.i32("dims[0] (theta_h)");
    dims[1] = in.i32("dims[1] (theta_d)");
    dims[2] = in.i32("dims[2] (phi_d)");
    if (dims[0] != kMerlThetaH || dims[1] != kMerlThetaD || dims[2] != kMerlPhiD)
        throw FormatError(path, "byte 0, dims",
                          "dims are " + std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " x " +
                              std::to_string(dims[2]) + "; MERL tables are 90 x 90 x 180");
    const size_t n = size_t(kMerlThetaH) * kMerlThetaD * kMerlPhiD;
    const uint64_t expected = 3 * uint64_t(n) * 8;
    if (in.remaining() != expected)
        in.fail("values", "expected 3 x 90 x 90 x 180 float64 values (" + std::to_string(expected) + " bytes), found " +
                              std::to_string(in.remaining()) + " bytes" +
                              (in.remaining() < expected ? " (truncated)" : " (trailing bytes)"));
    std::vector<double> raw(3 * n);
    in.read(raw.data(), expected, "values");

    constexpr double kDeg = kPiDouble / 180.0;
    Table t;
    t.parametrization = Parametrization::HalfDiff;
    t.channel_kind = ChannelKind::RGB;
    t.symmetry = kSymReciprocity;
    t.channels = 3;
    t.axes.resize(3);
    for (int i = 0; i < kMerlThetaH; ++i) t.axes[0].push_back(float(double(i) * i / 90.0 * kDeg));
    for (int j = 0; j < kMerlThetaD; ++j) t.axes[1].push_back(float(j * kDeg));
    for (int k = 0; k <= kMerlPhiD; ++k) t.axes[2].push_back(float(k * kDeg));

    static const double kScale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};
    static const char* kChannel[3] = {"red", "green", "blue"};
    const int phi_out = kMerlPhiD + 1;
    const size_t points = size_t(kMerlThetaH) * kMerlThetaD * phi_out;
    t.values.assign(points * 3, 0.0f);
    t.valid.assign(points, 1);
    size_t missing = 0;
    for (int h = 0; h < kMerlThetaH; ++h)
        for (int d = 0; d < kMerlThetaD; ++d)
            for (int p = 0; p < phi_out; ++p) {
                const size_t src = size_t(p % kMerlPhiD) + size_t(kMerlPhiD) * (d + size_t(kMerlThetaD) * h);
                const size_t dst = size_t(p) + size_t(phi_out) * (d + size_t(kMerlThetaD) * h);
                bool measured = true;
                for (int c = 0; c < 3; ++c) {
                    const double v = raw[c * n + src];
                    // finite doubles beyond float32 once scaled (1e300) would become inf in the table and fail
                    // its check as a ValueError without the file or the byte
                    const bool too_large = std::isfinite(v) && v * kScale[c] > double(FLT_MAX);  // negatives are masked
                    if (!std::isfinite(v) || too_large) {
                        char shown[32];
                        std::snprintf(shown, sizeof shown, "%g ", v);
                        throw FormatError(path, "byte " + std::to_string(12 + 8 * (c * n + src)),
                                          std::string(kChannel[c]) + " value " + (too_large ? shown : "") +
                                              "at theta_h bin " + std::to_string(h) + ", theta_d bin " +
                                              std::to_string(d) + ", phi_d bin " + std::to_string(p % kMerlPhiD) +
                                              (too_large ? " is too large for float32" : " is not finite"));
                    }
                    if (v < 0) measured = false;
                    t.values[dst * 3 + c] = float(v * kScale[c]);
                }
                if (!measured) {
                    for (int c = 0; c < 3; ++c) t.values[dst * 3 + c] = 0.0f;
                    t.valid[dst] = 0;
                    if (p < kMerlPhiD) ++missing;
                }
            }
    if (missing == 0) t.valid.clear();
    const size_t slash = path.find_last_of('/');
    t.provenance = "MERL BRDF database .binary (" + path.substr(slash == std::string::npos ? 0 : slash + 1) +
                   "); negative entries masked as missing: " + std::to_string(missing) + " of " + std::to_string(n) +
                   " points";
    return t;
}

}  // namespace patina
