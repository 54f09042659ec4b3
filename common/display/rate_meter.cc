#include "common/display/rate_meter.h"

namespace ephor::display {

RateMeter::RateMeter(double window_s) : window_s_(window_s > 0.0 ? window_s : 1.0) {}

void RateMeter::add_sample(double now_s, const std::map<std::string, uint64_t>& totals) {
  samples_.push_back({now_s, totals});
  // Keep one sample at or before the window's start so the span covers it.
  while (samples_.size() > 2 && samples_[1].t_s <= now_s - window_s_) samples_.pop_front();
}

std::map<std::string, double> RateMeter::rates() const {
  std::map<std::string, double> out;
  if (samples_.empty()) return out;
  const Sample& newest = samples_.back();
  const Sample& oldest = samples_.front();
  const double dt = newest.t_s - oldest.t_s;
  for (const auto& [channel, total] : newest.totals) {
    const auto it = oldest.totals.find(channel);
    const uint64_t before = it == oldest.totals.end() ? 0 : it->second;
    if (dt <= 0.0 || total < before) {
      out[channel] = 0.0;
    } else {
      out[channel] = static_cast<double>(total - before) / dt;
    }
  }
  return out;
}

}  // namespace ephor::display
