#pragma once
// The range process's clouds (paper 004, section 5: the points of every
// stripe of a scan together, "displayed in perspective"): each stripe's
// points kept by (scan, stripe index), a repeat ignored; a scan is complete
// once the scan planner has said how many stripes it captured and every one
// of them has been ranged, or that long after it said so with some never
// heard (their number reported). The cloud is the stripes in stripe order,
// each stripe's points in image-row order, so the same stripes give the same
// cloud whatever order they arrived in.
//
// Units: mm, table frame; times in s of any one clock.

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include <Eigen/Core>

namespace ephor::stripe {

struct CompletedCloud {
  int64_t scan_id = 0;
  std::vector<Eigen::Vector3d> points;
  int stripes = 0;          // stripes ranged
  int stripes_missing = 0;  // captured but never heard
};

class CloudAccumulator {
 public:
  explicit CloudAccumulator(double missing_timeout_s = 5.0) : timeout_s_(missing_timeout_s) {}

  // One stripe's points (scan_id > 0, stripe_index >= 0). False when it is a
  // repeat or its scan is already complete.
  bool add(int64_t scan_id, int stripe_index, std::vector<Eigen::Vector3d> points);
  // The planner's word that `captured` stripes were imaged (the scan's
  // STATE_CAPTURED). Repeats are harmless.
  void captured(int64_t scan_id, int captured, double now_s);
  // Scans complete now, oldest first; each is given once.
  std::vector<CompletedCloud> take_complete(double now_s);

  bool finished(int64_t scan_id) const { return finished_.count(scan_id) != 0; }
  int stripes(int64_t scan_id) const;
  int64_t points(int64_t scan_id) const;

 private:
  struct Scan {
    std::map<int, std::vector<Eigen::Vector3d>> stripes;
    int64_t points = 0;
    std::optional<int> captured;
    double captured_s = 0.0;
  };
  double timeout_s_;
  std::map<int64_t, Scan> scans_;
  std::set<int64_t> finished_;
};

}  // namespace ephor::stripe
