#pragma once
// The simulated world of the sphere system (paper 002, sections 3-4, and
// issue 15's approach): the chaser's scanning laser range finder and the
// drifting sphere, advanced on the scan clock (seconds since the ranger
// started). Every window [kW, (k+1)W) gets a fresh raster that starts at the
// upper left (as in each of the paper's trials), its frame 105 % of what
// the sphere needs during the window (RasterScanner's helper, with the
// sphere's growth as it closes in), and its own noise draws; the chaser's
// velocity changes only at window boundaries (RelativeMotion), so the scan
// of each window is the paper's linear-motion case exactly.
//
// It also judges each approach (CaptureJudge) and, with several approaches,
// puts a fresh sphere at the start distance after each verdict. Pure: no
// LCM, no clocks; ephor-sphere-ranger drives it with the real time.

#include <cstdint>
#include <deque>
#include <optional>
#include <random>
#include <vector>

#include "common/sphere/range_simulator.h"
#include "common/sphere/raster_scanner.h"
#include "common/sphere/scan_types.h"
#include "common/sphere/world/capture_judge.h"
#include "common/sphere/world/relative_motion.h"

namespace ephor::sphere {

struct RangerWorldConfig {
  RelativeMotionConfig motion;  // start, drift, chaser, acceleration limit, window
  RasterScannerConfig scanner;  // rates and pulse rate (the half extent is sized per window)
  RangeNoise noise;             // section 3
  FarBackground background;     // off by default
  CaptureCriteria capture;
  double extent_margin = 1.05;  // section 4: 105 % of the extent needed
  double max_half_extent_deg = 45.0;
  double max_s = 0.0;  // give up an approach after this long (0 = never)
  int approaches = 1;  // 0 = until stopped
  uint64_t seed = 1;
};

// A scan line with what the locator needs to cut windows.
struct RangerLine {
  int64_t window = 0;
  bool last_in_window = false;
  double half_extent_deg = 0.0;
  ScanLine line;
  double ready_t_s = 0.0;  // time of its last pulse: when it can be published
};

struct RangerTruth {
  double t_s = 0.0;
  int approach = 0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d chaser_velocity_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d target_velocity_m_s = Eigen::Vector3d::Zero();
  double half_extent_deg = 0.0;
};

class RangerWorld {
 public:
  // Throws std::invalid_argument for a bad setting (names it).
  explicit RangerWorld(const RangerWorldConfig& config);

  // The newest guidance command: from apply_t_s on, fly `chaser_velocity`.
  // It takes effect at the first window start at or after apply_t_s (a
  // command that arrives late waits for the next window). Non-finite
  // commands are refused (returns false).
  bool command(double apply_t_s, const Eigen::Vector3d& chaser_velocity_m_s);

  // Advances to t_s (not backwards): starts each window whose start is <=
  // t_s, judges the approach up to t_s, and returns the lines whose last
  // pulse is at or before t_s that were not returned before, in order.
  std::vector<RangerLine> advance_to(double t_s);

  // The truth at t_s (within the current window; linear motion).
  RangerTruth truth_at(double t_s) const;

  // One verdict per finished approach, in order.
  const std::vector<CaptureVerdict>& verdicts() const { return verdicts_; }
  // All approaches judged.
  bool finished() const;
  int approach() const { return approach_; }
  int64_t windows_started() const { return next_window_; }
  const RelativeMotion& motion() const { return motion_; }
  const RangerWorldConfig& config() const { return config_; }

 private:
  void start_window(int64_t k);
  void judge_until(double t_s);

  struct Command {
    double apply_t_s;
    Eigen::Vector3d chaser_velocity_m_s;
  };

  RangerWorldConfig config_;
  RelativeMotion motion_;
  CaptureJudge judge_;
  std::mt19937_64 rng_;  // drift of later approaches
  std::deque<Command> commands_;
  Eigen::Vector3d flown_command_;  // the command in force
  int64_t next_window_ = 0;
  int64_t next_line_id_ = 0;
  double half_extent_deg_ = 0.0;
  double judged_until_s_ = 0.0;
  double approach_start_s_ = 0.0;
  int approach_ = 0;
  bool awaiting_reset_ = false;  // verdict given: the next window brings a new sphere
  std::deque<RangerLine> pending_;
  std::vector<CaptureVerdict> verdicts_;
};

}  // namespace ephor::sphere
