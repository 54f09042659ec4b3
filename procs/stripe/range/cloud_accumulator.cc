#include "procs/stripe/range/cloud_accumulator.h"

namespace ephor::stripe {

bool CloudAccumulator::add(int64_t scan_id, int stripe_index, std::vector<Eigen::Vector3d> points) {
  if (scan_id <= 0 || stripe_index < 0 || finished(scan_id)) return false;
  Scan& s = scans_[scan_id];
  if (s.stripes.count(stripe_index) != 0) return false;
  s.points += static_cast<int64_t>(points.size());
  s.stripes.emplace(stripe_index, std::move(points));
  return true;
}

void CloudAccumulator::captured(int64_t scan_id, int captured, double now_s) {
  if (scan_id <= 0 || finished(scan_id)) return;
  Scan& s = scans_[scan_id];
  if (s.captured) return;
  s.captured = captured;
  s.captured_s = now_s;
}

std::vector<CompletedCloud> CloudAccumulator::take_complete(double now_s) {
  std::vector<CompletedCloud> out;
  for (auto it = scans_.begin(); it != scans_.end();) {
    const Scan& s = it->second;
    const int heard = static_cast<int>(s.stripes.size());
    const bool all = s.captured && heard >= *s.captured;
    const bool given_up = s.captured && now_s - s.captured_s >= timeout_s_;
    if (!all && !given_up) {
      ++it;
      continue;
    }
    CompletedCloud c;
    c.scan_id = it->first;
    c.stripes = heard;
    c.stripes_missing = std::max(0, *s.captured - heard);
    c.points.reserve(static_cast<size_t>(s.points));
    for (const auto& [index, points] : s.stripes)
      c.points.insert(c.points.end(), points.begin(), points.end());
    out.push_back(std::move(c));
    finished_.insert(it->first);
    it = scans_.erase(it);
  }
  return out;
}

int CloudAccumulator::stripes(int64_t scan_id) const {
  const auto it = scans_.find(scan_id);
  return it == scans_.end() ? 0 : static_cast<int>(it->second.stripes.size());
}

int64_t CloudAccumulator::points(int64_t scan_id) const {
  const auto it = scans_.find(scan_id);
  return it == scans_.end() ? 0 : it->second.points;
}

}  // namespace ephor::stripe
