#pragma once
// SafetyGate: the arm process's own reasons to stop, independent of what the
// planner or comm believe (issue 6, "safety and trust at the boundary").
//
// - Emergency stop (ESTOP, estop_t): latched. While latched every command is
//   refused and a motion in progress is stopped; released only by an
//   explicit release message.
// - Comm watchdog: while a motion runs, comm re-sends its command every
//   poll interval (200 ms by default, procs/shared/comm GoalRelay). If nothing has
//   been heard from comm for `comm_timeout_us`, the motion is stopped: the
//   machine that planned it may be gone, and nobody would hear its DONE.
//
// Pure logic fed with a monotonic clock in us; not thread safe (one owner).

#include <cstdint>
#include <optional>
#include <string>

namespace ephor::arm {

struct SafetyGateConfig {
  int64_t comm_timeout_us = 1'000'000;  // 0 = no comm watchdog
};

class SafetyGate {
 public:
  explicit SafetyGate(SafetyGateConfig config = {}) : config_(config) {}

  // An estop_t arrived. Returns true when the latch changed.
  bool on_estop(bool stop, const std::string& sender, const std::string& reason);
  // A command from the trusted comm sender arrived (first send or poll).
  void on_comm_heard(int64_t now_us) { last_comm_us_ = now_us; }

  // Why a new command must be refused now, if it must.
  std::optional<std::string> refuse_command() const;
  // Why a motion in progress must be stopped now, if it must. Call every
  // control period with `moving` = a motion is being executed.
  std::optional<std::string> stop_reason(bool moving, int64_t now_us) const;

  bool estopped() const { return estopped_; }

 private:
  SafetyGateConfig config_;
  bool estopped_ = false;
  std::string estop_why_;
  int64_t last_comm_us_ = 0;
};

}  // namespace ephor::arm
