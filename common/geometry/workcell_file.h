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

// What a process's --workcell flag means: an empty path is the compiled-in
// default (the shepherding field of workcell.h); a relative path is looked up
// from the working directory, then the repository (resolve_repo_path). Every
// process of a system gets the same file from its manifest, so the work cell
// comes from one place.
Workcell workcell_from_flag(const std::string& path);

}  // namespace ephor::geometry
