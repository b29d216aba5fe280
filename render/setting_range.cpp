#include "render/setting_range.h"

#include <sstream>
#include <stdexcept>
#include <string>

namespace patina {
namespace {

// an integer setting's values in full (1048576, not 1.04858e+06), a number's as written
std::string shown(double v, bool integer) {
    if (integer) return std::to_string(static_cast<long long>(v));
    std::ostringstream o;
    o << v;
    return o.str();
}

}  // namespace

bool in_setting_range(bool integer, double lo, double hi, double v) {
    if (integer) return v >= lo && v <= hi;
    const float f = static_cast<float>(v);
    return f >= static_cast<float>(lo) && f <= static_cast<float>(hi);
}

void fail_setting_range(const std::string& name, bool integer, double lo, double hi, double v) {
    const std::string range = integer ? "an integer from " + shown(lo, true) + " to " + shown(hi, true)
                                      : "a number in [" + shown(lo, false) + ", " + shown(hi, false) + "]";
    throw std::invalid_argument(name + ": must be " + range + ", got " + shown(v, integer));
}

}  // namespace patina
