#pragma once
// Logging for every ephor process: spdlog with one pattern, so the launcher's
// "[process] " prefix plus this line reads well in a terminal and in logs.

#include <string>

#include <spdlog/spdlog.h>

namespace ephor {

// Sets the global spdlog pattern and level. Level names as spdlog's
// ("trace", "debug", "info", "warn", "error"); taken from EPHOR_LOG_LEVEL when
// that is set.
void init_logging(const std::string& process_name);

}  // namespace ephor
