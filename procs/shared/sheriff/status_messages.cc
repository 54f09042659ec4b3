#include "procs/shared/sheriff/status_messages.h"

namespace ephor::sheriff {

void StatusInbox::receive(const deputy_status_t& status, int64_t received_wall_us) {
  std::lock_guard<std::mutex> lock(mutex_);
  statuses_.emplace_back(status, received_wall_us);
}

bool StatusInbox::drain(Sheriff& sheriff, int64_t now_ns) {
  std::deque<std::pair<deputy_status_t, int64_t>> batch;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    batch.swap(statuses_);
  }
  for (const auto& [s, received_us] : batch) sheriff.on_status(s, now_ns, received_us);
  return !batch.empty();
}

std::string table_signature(const Sheriff& sheriff, int64_t now_ns) {
  std::string sig;
  for (const auto& h : sheriff.hosts())
    sig += h.name + (now_ns - h.last_status_ns < 2'500'000'000 ? "+" : "-");
  for (const auto& p : sheriff.processes()) {
    sig += "|" + p.host + "/" + p.name + (p.desired_run ? "1" : "0");
    if (p.reported)
      sig += p.reported->state + std::to_string(p.reported->pid) +
             std::to_string(p.reported->restarts);
  }
  return sig;
}

}  // namespace ephor::sheriff
