#pragma once
// The sheep a recorded run started with, for replaying its start on the
// kinematic stand-in (ephor-bench-planner --start): read from a
// GROUND_TRUTH row as `tools/ephor log export run.lcm --channel GROUND_TRUTH
// --json` writes it, one JSON object per line:
//   {"channel": "GROUND_TRUTH", ..., "msg": {"sheep": [{"id": 1, "x_mm": ..,
//    "y_mm": .., "heading_rad": .., "speed_mm_s": .., "on_field": true}, ..]}}
// Positions in F (mm), heading in rad about +z of F, speed in mm/s. Sheep
// off the field (escaped, waiting to re-enter) are left out.

#include <string>
#include <vector>

#include "procs/shepherd/planner/herd_types.h"

namespace ephor::planner {

// Throws std::invalid_argument naming the problem: not JSON, no msg.sheep
// array, a sheep field missing, not a number or not finite, no sheep on the
// field.
std::vector<Sheep> sheep_from_ground_truth_row(const std::string& json_line);

// The first line of `path`. Throws std::invalid_argument as above, or when
// the file cannot be read or is empty.
std::vector<Sheep> sheep_from_ground_truth_file(const std::string& path);

}  // namespace ephor::planner
