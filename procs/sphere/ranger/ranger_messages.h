#pragma once
// ephor-sphere-ranger's handler and tasks on its world (out of main.cc, so
// that the fuzz target ranger_messages_fuzz.cc runs what the process runs):
// SPHERE_GUIDANCE as RangerWorld::command(), the scan task's lines and
// verdicts as the SPHERE_SCAN_LINE and SPHERE_TRUTH it publishes, and the
// truth task's SPHERE_TRUTH. Sensor frame, metres, m/s; t_s is the scan
// clock (seconds since start-up), a message's utime the wall clock at start
// plus t_s.
//
// Threading: the handler and the tasks may run on different threads; each
// takes mutex() for the world. Counts are atomic.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <vector>

#include "common/sphere/world/ranger_world.h"
#include "ephor/sphere_guidance_t.hpp"
#include "ephor/sphere_scan_line_t.hpp"
#include "ephor/sphere_truth_t.hpp"

namespace ephor::sphere {

// A scan line as SPHERE_SCAN_LINE (utime: when its last pulse was measured).
sphere_scan_line_t scan_line_message(const RangerLine& l, double window_s, int64_t utime);
// The truth's fields of SPHERE_TRUTH (utime, phase and the verdict's are the caller's).
void fill_truth(sphere_truth_t& m, const RangerTruth& t);

class RangerProcess {
 public:
  // `world` outlives this; `wall0_us`: the wall clock at scan time 0.
  RangerProcess(RangerWorld& world, int64_t wall0_us);

  // SPHERE_GUIDANCE: the chaser's velocity from apply_t_s on. A command with
  // a time or velocity that is not finite is refused, counted and logged
  // (the first ten, then every hundredth: a sender repeating it does not
  // flood the log); returns whether it was taken.
  bool on_guidance(const sphere_guidance_t& m);

  struct Scan {
    std::vector<sphere_scan_line_t> lines;  // SPHERE_SCAN_LINE, in order
    std::vector<sphere_truth_t> verdicts;   // SPHERE_TRUTH, one per new verdict
  };
  // Task "scan": the world advanced to t_s (not backwards), its new lines and verdicts.
  Scan scan(double t_s);
  // Task "truth": SPHERE_TRUTH at t_s, or nothing once finished or while
  // the scan lags (no window covers t_s yet).
  std::optional<sphere_truth_t> truth(double t_s);

  bool finished() const { return finished_; }
  int64_t commands() const { return commands_; }
  int64_t commands_refused() const { return commands_refused_; }
  int64_t lines_published() const { return lines_published_; }
  int64_t utime_of(double t_s) const;
  std::mutex& mutex() { return mutex_; }

 private:
  RangerWorld& world_;
  const int64_t wall0_us_;
  std::mutex mutex_;
  std::atomic<int64_t> lines_published_{0}, commands_{0}, commands_refused_{0};
  std::atomic<bool> finished_{false};
  size_t verdicts_published_ = 0;  // under mutex_
};

}  // namespace ephor::sphere
