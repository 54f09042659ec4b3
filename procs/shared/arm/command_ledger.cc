#include "procs/shared/arm/command_ledger.h"

namespace ephor::arm {

std::optional<ArmAck> CommandLedger::find(int64_t seq, int64_t first_sent_utime) const {
  const auto it = acks_.find({seq, first_sent_utime});
  if (it == acks_.end()) return std::nullopt;
  return it->second;
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
