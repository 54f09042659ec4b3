#include "procs/shared/arm/safety_gate.h"

#include <spdlog/fmt/fmt.h>

namespace ephor::arm {

bool SafetyGate::on_estop(bool stop, const std::string& sender, const std::string& reason) {
  if (stop == estopped_) return false;
  estopped_ = stop;
  estop_why_ = stop ? fmt::format("emergency stop from '{}': {}", sender,
                                  reason.empty() ? "no reason given" : reason)
                    : std::string();
  return true;
}

std::optional<std::string> SafetyGate::refuse_command() const {
  if (estopped_) return estop_why_ + " (send ESTOP stop=false to release)";
  return std::nullopt;
}

std::optional<std::string> SafetyGate::stop_reason(bool moving, int64_t now_us) const {
  if (!moving) return std::nullopt;
  if (estopped_) return estop_why_;
  if (config_.comm_timeout_us > 0 && now_us - last_comm_us_ > config_.comm_timeout_us) {
    return fmt::format("nothing heard from comm for {:.0f} ms (limit {:.0f} ms): stopped",
                       static_cast<double>(now_us - last_comm_us_) / 1e3,
                       static_cast<double>(config_.comm_timeout_us) / 1e3);
  }
  return std::nullopt;
}

}  // namespace ephor::arm
