#pragma once
// Loading ephor-sim's text configuration (procs/shepherd/sim/sim_config.proto) onto a
// SimulatorConfig.

#include <string>

#include "common/shepherd/sim/simulator.h"

namespace ephor::sim {

// Reads `path` and overwrites the fields it sets in `config` and `fps`. Throws
// ephor::ConfigError "path:line: field: problem" on a syntax error, an unknown
// field or a value the simulator refuses.
void apply_config_file(const std::string& path, SimulatorConfig& config, double& fps);

}  // namespace ephor::sim
