#pragma once
// Where the repository's data files (deploy/, calibration files) are, for
// processes that default to one of them.

#include <filesystem>
#include <string>

namespace ephor {

// $EPHOR_SOURCE_DIR when set, else the source tree this binary was built
// from (when it still exists), else two levels above the executable
// (build/bin/..).
std::filesystem::path repo_dir();

// repo_dir()/deploy/calibration/sim.pbtxt: the simulator's calibration.
std::string default_calibration_path();

}  // namespace ephor
