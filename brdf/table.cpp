#include "table.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace patina {

int axis_count(Parametrization p) { return p == Parametrization::Anisotropic ? 4 : 3; }

const char* parametrization_name(Parametrization p) {
    switch (p) {
        case Parametrization::Isotropic: return "isotropic";
        case Parametrization::Anisotropic: return "anisotropic";
        case Parametrization::HalfDiff: return "halfdiff";
    }
    return "unknown";
}

const char* channel_kind_name(ChannelKind k) {
    switch (k) {
        case ChannelKind::Mono: return "mono";
        case ChannelKind::RGB: return "rgb";
        case ChannelKind::XYZ: return "xyz";
        case ChannelKind::Spectral: return "spectral";
    }
    return "unknown";
}

const char* axis_name(Parametrization p, int axis) {
    static const char* iso[] = {"theta_i", "theta_o", "phi_d"};
    static const char* aniso[] = {"theta_i", "phi_i", "theta_o", "phi_o"};
    static const char* hd[] = {"theta_h", "theta_d", "phi_d"};
    if (axis < 0 || axis >= axis_count(p)) return "?";
    switch (p) {
        case Parametrization::Isotropic: return iso[axis];
        case Parametrization::Anisotropic: return aniso[axis];
        case Parametrization::HalfDiff: return hd[axis];
    }
    return "?";
}

size_t Table::point_count() const {
    size_t n = 1;
    for (const auto& a : axes) n *= a.size();
    return axes.empty() ? 0 : n;
}

size_t Table::missing_count() const {
    size_t n = 0;
    for (uint8_t v : valid) n += v ? 0 : 1;
    return n;
}

void Table::check() const {
    using std::to_string;
    const int dims = axis_count(parametrization);
    if (static_cast<int>(axes.size()) != dims)
        throw std::invalid_argument(std::string(parametrization_name(parametrization)) + " table needs " +
                                    to_string(dims) + " axes, got " + to_string(axes.size()));
    for (int a = 0; a < dims; ++a) {
        const auto& k = axes[a];
        const std::string name = axis_name(parametrization, a);
        if (k.size() < 2) throw std::invalid_argument("axis " + name + " needs at least 2 knots");
        for (size_t j = 0; j < k.size(); ++j) {
            if (!std::isfinite(k[j]))
                throw std::invalid_argument("axis " + name + " knot " + to_string(j) + " is not finite");
            if (j && !(k[j] > k[j - 1]))
                throw std::invalid_argument("axis " + name + " is not strictly increasing at knot " + to_string(j));
        }
        if (k.front() < -7.0f || k.back() > 7.0f)
            throw std::invalid_argument("axis " + name + " is outside [-2 pi, 2 pi]: are the angles in radians?");
    }
    if (channels < 1) throw std::invalid_argument("a table needs at least one channel");
    if (channel_kind == ChannelKind::RGB && channels != 3) throw std::invalid_argument("rgb table needs 3 channels");
    if (channel_kind == ChannelKind::XYZ && channels != 3) throw std::invalid_argument("xyz table needs 3 channels");
    if (channel_kind == ChannelKind::Mono && channels != 1) throw std::invalid_argument("mono table needs 1 channel");
    if (channel_kind == ChannelKind::Spectral) {
        if (wavelengths.size() != static_cast<size_t>(channels))
            throw std::invalid_argument("spectral table needs one wavelength per channel");
        for (size_t j = 1; j < wavelengths.size(); ++j)
            if (!(wavelengths[j] > wavelengths[j - 1]))
                throw std::invalid_argument("wavelengths are not strictly increasing at " + to_string(j));
    } else if (!wavelengths.empty()) {
        throw std::invalid_argument("only spectral tables carry wavelengths");
    }
    const size_t points = point_count();
    // The kernels index values with 32-bit lanes.
    if (points * static_cast<size_t>(channels) >= (size_t(1) << 31))
        throw std::invalid_argument("table has more than 2^31 values");
    if (values.size() != points * static_cast<size_t>(channels))
        throw std::invalid_argument("values hold " + to_string(values.size()) + " numbers, the grid needs " +
                                    to_string(points * channels));
    if (!valid.empty() && valid.size() != points)
        throw std::invalid_argument("validity mask has " + to_string(valid.size()) + " entries, the grid has " +
                                    to_string(points));
    for (size_t j = 0; j < values.size(); ++j)
        if (!std::isfinite(values[j]))
            throw std::invalid_argument("value " + to_string(j) + " (grid point " + to_string(j / channels) +
                                        ", channel " + to_string(j % channels) + ") is not finite");
}

PreparedTable prepare(const Table& table) {
    table.check();
    PreparedTable p;
    TableView& v = p.view;
    v.parametrization = table.parametrization;
    v.symmetry = table.symmetry;
    v.dims = axis_count(table.parametrization);
    v.channels = table.channels;
    int32_t stride = 1;
    for (int a = v.dims - 1; a >= 0; --a) {
        const auto& k = table.axes[a];
        v.knots[a] = k.data();
        p.inv_widths[a].resize(k.size() - 1);
        for (size_t i = 0; i + 1 < k.size(); ++i) p.inv_widths[a][i] = 1.0f / (k[i + 1] - k[i]);
        v.inv_widths[a] = p.inv_widths[a].data();
        v.lengths[a] = static_cast<int>(k.size());
        v.strides[a] = stride;
        stride *= v.lengths[a];
    }
    for (int a = v.dims; a < kMaxAxes; ++a) {
        v.knots[a] = nullptr;
        v.inv_widths[a] = nullptr;
        v.lengths[a] = 0;
        v.strides[a] = 0;
    }
    p.values.reserve(table.values.size() + kValuePadding);
    p.values.assign(table.values.begin(), table.values.end());
    p.values.resize(table.values.size() + kValuePadding, 0.0f);
    v.values = p.values.data();
    v.coverage = nullptr;
    if (table.missing_count() > 0) {
        p.coverage.resize(table.valid.size());
        for (size_t j = 0; j < table.valid.size(); ++j) p.coverage[j] = table.valid[j] ? 1.0f : 0.0f;
        v.coverage = p.coverage.data();
    }
    return p;
}

}  // namespace patina
