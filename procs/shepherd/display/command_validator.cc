#include "procs/shepherd/display/command_validator.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <optional>

namespace ephor::display {
namespace {

CommandResult refuse(std::string reason) {
  CommandResult r;
  r.reason = std::move(reason);
  return r;
}

CommandResult accept(Target target, Controls controls) {
  CommandResult r;
  r.ok = true;
  r.target = target;
  r.controls = std::move(controls);
  return r;
}

// The parameter's value, or nullopt when absent.
std::optional<std::string> param(const std::map<std::string, std::string>& params,
                                 const std::string& key) {
  const auto it = params.find(key);
  if (it == params.end()) return std::nullopt;
  return it->second;
}

std::optional<bool> parse_bool(const std::string& s) {
  if (s == "true" || s == "1") return true;
  if (s == "false" || s == "0") return false;
  return std::nullopt;
}

// Whole string must be a decimal integer within [lo, hi].
// strtol/strtod skip leading blanks and accept '+': the page never sends
// either, so they are refused as malformed.
bool plain_number_start(const std::string& s) {
  return !s.empty() && (s[0] == '-' || s[0] == '.' || (s[0] >= '0' && s[0] <= '9'));
}

std::optional<long> parse_int(const std::string& s, long lo, long hi) {
  if (!plain_number_start(s) || s.size() > 12) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (errno != 0 || end != s.c_str() + s.size() || v < lo || v > hi) return std::nullopt;
  return v;
}

// Whole string must be a finite number within [lo, hi].
std::optional<double> parse_double(const std::string& s, double lo, double hi) {
  if (!plain_number_start(s) || s.size() > 32) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (errno != 0 || end != s.c_str() + s.size() || !std::isfinite(v) || v < lo || v > hi) {
    return std::nullopt;
  }
  return v;
}

}  // namespace

CommandValidator::CommandValidator(int image_width_px, int image_height_px)
    : width_px_(image_width_px), height_px_(image_height_px) {}

void CommandValidator::set_image_size(int width_px, int height_px) {
  width_px_ = width_px;
  height_px_ = height_px;
}

CommandResult CommandValidator::validate(const std::string& command,
                                         const std::map<std::string, std::string>& params,
                                         const Controls& current) const {
  Controls next = current;
  if (command == "box") {
    const auto u = param(params, "u");
    const auto v = param(params, "v");
    if (!u || !v) return refuse("box needs u and v (image px)");
    const auto pu = parse_double(*u, 0.0, static_cast<double>(width_px_ - 1));
    if (!pu)
      return refuse("box u '" + *u + "' is not a number in 0.." + std::to_string(width_px_ - 1) +
                    " px");
    const auto pv = parse_double(*v, 0.0, static_cast<double>(height_px_ - 1));
    if (!pv)
      return refuse("box v '" + *v + "' is not a number in 0.." + std::to_string(height_px_ - 1) +
                    " px");
    next.box.u = *pu;
    next.box.v = *pv;
    if (const auto h = param(params, "half")) {
      const auto ph = parse_double(*h, 2.0, 200.0);
      if (!ph) return refuse("box half '" + *h + "' is not a number in 2..200 px");
      next.box.half_size_px = *ph;
    }
    next.box.visible = true;
    if (const auto vis = param(params, "visible")) {
      const auto b = parse_bool(*vis);
      if (!b) return refuse("box visible '" + *vis + "' is neither true nor false");
      next.box.visible = *b;
    }
    return accept(Target::kBox, next);
  }

  const auto value = param(params, "value");
  if (command != "pause" && command != "mode" && command != "scan" && command != "planner" &&
      command != "sheep") {
    // estop never gets here (DisplayServer answers it) but is one of the page's commands.
    return refuse("unknown command '" + command +
                  "' (want pause, mode, scan, planner, sheep, box or estop)");
  }
  if (!value) return refuse(command + " needs a value");
  const std::string& s = *value;
  if (command == "pause") {
    const auto b = parse_bool(s);
    if (!b) return refuse("pause value '" + s + "' is neither true nor false");
    next.vision.paused = *b;
    return accept(Target::kVision, next);
  }
  if (command == "mode") {
    if (s == "blobify") {
      next.vision.mode = 0;
    } else if (s == "trackify") {
      next.vision.mode = 1;
    } else {
      return refuse("mode '" + s + "' is neither blobify nor trackify");
    }
    return accept(Target::kVision, next);
  }
  if (command == "scan") {
    if (s == "full") {
      next.vision.scan = 0;
    } else if (s == "axis") {
      next.vision.scan = 1;
    } else {
      return refuse("scan '" + s + "' is neither full nor axis");
    }
    return accept(Target::kVision, next);
  }
  if (command == "planner") {
    if (s != "single" && s != "multi" && s != "lookahead") {
      return refuse("planner '" + s + "' is not single, multi or lookahead");
    }
    next.planner = s;
    return accept(Target::kPlanner, next);
  }
  // sheep
  const auto n = parse_int(s, 0, 64);
  if (!n) return refuse("sheep '" + s + "' is not an integer in 0..64");
  next.sim.sheep = static_cast<int>(*n);
  return accept(Target::kSim, next);
}

}  // namespace ephor::display
