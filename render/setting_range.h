// A setting's allowed range, declared once in a table beside its struct: the C++ check reads
// the table, and so do the Python scene reader's and the command line's messages (through the
// bindings' *_ranges functions), so no second copy can drift.
#pragma once

#include <cstddef>
#include <string>

namespace patina {

template <class Settings>
struct SettingRange {
    const char* key;  // the field's name, the scene file's key and (with dashes) the command line's option
    bool integer;     // an integer setting (else a number)
    double lo, hi;    // inclusive; a float setting is compared in float (0.01 means 0.01f)
    double (*value)(const Settings&);
};

// v within [lo, hi] (a float setting compared in float, as the scene file's 0.01 arrives: 0.01f)
bool in_setting_range(bool integer, double lo, double hi, double v);

// Throws std::invalid_argument "<name>: must be an integer from lo to hi, got v" (or "a number in [lo, hi]").
[[noreturn]] void fail_setting_range(const std::string& name, bool integer, double lo, double hi, double v);

// Each setting of the table checked against its range; the first one out of it is named as
// prefix + key.
template <class Settings, size_t N>
void check_setting_ranges(const SettingRange<Settings> (&table)[N], const Settings& s, const char* prefix) {
    for (const SettingRange<Settings>& r : table) {
        const double v = r.value(s);
        if (!in_setting_range(r.integer, r.lo, r.hi, v)) fail_setting_range(prefix + std::string(r.key), r.integer, r.lo, r.hi, v);
    }
}

}  // namespace patina
