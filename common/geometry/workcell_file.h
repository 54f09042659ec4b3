#pragma once
// Loads a work cell text file (common/geometry/workcell.proto): what each
// system's manifest gives ephor-arm and its simulator with --workcell FILE.

#include <string>

#include "common/geometry/workcell.h"

namespace ephor::geometry {

// Throws ephor::ConfigError naming the file, line and field on a missing
// file, a syntax error, an unknown field, or a value that is not finite or
// out of range (sizes and tool length must be > 0).
Workcell load_workcell_file(const std::string& path);

}  // namespace ephor::geometry
