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

// A data file named on a command line or in a manifest: `path` itself when
// absolute or when it exists relative to the working directory, else
// repo_dir()/path (manifests name files like "deploy/catch/board.pbtxt"
// whatever directory the launcher was started from).
std::string resolve_repo_path(const std::string& path);

// repo_dir()/deploy/calibration/sim.pbtxt: the simulator's calibration.
std::string default_calibration_path();

}  // namespace ephor
