#pragma once
// Loads RAMBO's target model file (common/rambo/target_model.proto, Protobuf
// text): the polyhedron's vertices and faces, its diodes with their axes and
// goal points, and its principal moments. What the simulator and the pose,
// predictor and planner processes are given with --model FILE (one file per
// run, from deploy/rambo.pbtxt), so that all of them see the same target.

#include <string>

#include "common/rambo/rambo_cell.h"

namespace ephor::rambo {

// Throws ephor::ConfigError "path:line: field: problem" (one line) on a
// missing file, a syntax error, an unknown field, fewer than 4 vertices, a
// coordinate that is not a finite number, a face with fewer than 3 vertices
// or that names a missing vertex (which face, which index), a model that is
// not convex, more than RamboCell::kMaxDiodes diodes, a diode whose lens is
// off the target's surface (which, and how far) or whose axis does not point
// out of it, a standoff outside (0, 1000] mm, or moments that are not > 0.
TargetSpec load_target_model_file(const std::string& path);

// The same from text in memory; `name` stands for the file in messages.
TargetSpec parse_target_model(const std::string& text, const std::string& name);

// What a process's --model flag means: empty = RamboCell::builtin_target();
// a relative path is looked up from the working directory, then the
// repository (resolve_repo_path).
TargetSpec target_from_flag(const std::string& path);

// What a process's --model and --diodes flags mean together: the cell with
// the model's first `diode_count` diodes (0 = all of them). Throws
// ConfigError (one line) for a bad model or a count beyond the model's.
RamboCell cell_from_flags(const std::string& model_path, int diode_count);

}  // namespace ephor::rambo
