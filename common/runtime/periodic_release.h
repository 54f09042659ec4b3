#pragma once
// Release times of a periodic task on CLOCK_MONOTONIC (ns). Pure logic, so
// the overrun rule is unit-tested without a clock.
//
// Releases are r_k = phase + k * period. After a job that ends at `now`, the
// next job is released at the first r_k after the previous release; when the
// job overran and whole periods have already passed, those releases are
// skipped (counted) and the task restarts on the newest release not in the
// future, so it runs on fresh data instead of replaying a backlog.

#include <cstdint>

namespace ephor {

class PeriodicRelease {
 public:
  PeriodicRelease(int64_t first_release_ns, int64_t period_ns);

  int64_t period_ns() const { return period_ns_; }
  // Release time of the next job.
  int64_t next_release_ns() const { return next_ns_; }

  // Call when the job released at next_release_ns() has finished at now_ns.
  // Advances next_release_ns(); returns how many releases were skipped.
  int advance(int64_t now_ns);

  // Changes the period from the next release on (keeps the current phase).
  void set_period(int64_t period_ns);

  // Call instead of advance() to lock the phase to an external event: the
  // next release becomes the first anchor_ns + k * period after now_ns
  // (k may be negative). Used to release a camera-rate task just after each
  // frame arrives, like a frame grabber's vertical sync.
  void align(int64_t anchor_ns, int64_t now_ns);

 private:
  int64_t next_ns_;
  int64_t period_ns_;
};

}  // namespace ephor
