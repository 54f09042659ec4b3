#include "common/log/log.h"

#include <cstdlib>

namespace ephor {

void init_logging(const std::string& process_name) {
  // When started by the launcher the process name is already the line prefix;
  // standalone, it is useful in the line itself.
  const bool launched = std::getenv("EPHOR_LAUNCHED") != nullptr;
  spdlog::set_pattern(launched ? "%H:%M:%S.%e %^%L%$ %v"
                               : "%H:%M:%S.%e %^%L%$ [" + process_name + "] %v");
  if (const char* level = std::getenv("EPHOR_LOG_LEVEL")) {
    spdlog::set_level(spdlog::level::from_str(level));
  }
  spdlog::flush_on(spdlog::level::info);
}

}  // namespace ephor
