// Patina's native table format, .ptab (specified in docs/ptab.md).
#pragma once

#include <string>

#include "brdf/table.h"

namespace patina {

constexpr uint32_t kPtabVersion = 1;

// Throws FormatError naming the file, the byte offset and field, and the problem.
Table read_ptab(const std::string& path);

// Checks the table, then writes it atomically (temporary file + rename).
void write_ptab(const Table& table, const std::string& path);

}  // namespace patina
