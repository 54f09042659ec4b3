#include "procs/shared/arm/command_ledger.h"

#include <spdlog/fmt/fmt.h>

namespace ephor::arm {

std::optional<ArmAck> CommandLedger::find(int64_t seq, int64_t first_sent_utime) const {
  const auto it = acks_.find({seq, first_sent_utime});
  if (it == acks_.end()) return std::nullopt;
  return it->second;
}

std::optional<std::string> CommandLedger::refusal(int64_t seq, int64_t first_sent_utime) const {
  if (first_sent_utime >= started_utime_) return std::nullopt;
  // In double: a corrupt utime (e.g. INT64_MIN) must not overflow the difference.
  const double before_s =
      (static_cast<double>(started_utime_) - static_cast<double>(first_sent_utime)) / 1e6;
  return fmt::format(
      "not executed: seq {} was first sent {:.3f} s before this arm started (a restart): the arm "
      "that ran then may have executed it, and this one cannot know; send the goal again as a new "
      "command",
      seq, before_s);
}

void CommandLedger::record(int64_t seq, int64_t first_sent_utime, const ArmAck& ack) {
  const Key key{seq, first_sent_utime};
  const auto [it, inserted] = acks_.insert_or_assign(key, ack);
  (void)it;
  if (!inserted) return;
  order_.push_back(key);
  while (order_.size() > capacity_) {
    acks_.erase(order_.front());
    order_.pop_front();
  }
}

}  // namespace ephor::arm
