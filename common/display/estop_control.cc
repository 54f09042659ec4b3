#include "common/display/estop_control.h"

namespace ephor::display {

std::optional<bool> EstopControl::parse(const std::optional<std::string>& value, std::string& why) {
  if (!value) {
    why = "estop needs a value";
    return std::nullopt;
  }
  if (*value == "true" || *value == "1") return true;
  if (*value == "false" || *value == "0") return false;
  why = "estop value '" + *value + "' is neither true nor false";
  return std::nullopt;
}

const char* EstopControl::reason(bool stop) {
  return stop ? "operator pressed STOP on the display page"
              : "operator pressed release on the display page";
}

}  // namespace ephor::display
