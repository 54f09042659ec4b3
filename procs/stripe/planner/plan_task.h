#pragma once
// ephor-stripe-planner's plan task, out of main.cc so that the fuzz target
// stripe_planner runs the process's own flow: the first scan planned from
// where the arm is once it reports, each event given to the ScanSequencer,
// its tick, the scan's end (summary), the pause and the next scan. Joints in
// rad, lengths in mm, times in s of the process's monotonic clock.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/arm/puma560.h"
#include "common/stripe/scan_geometry.h"
#include "procs/stripe/planner/planner_messages.h"
#include "procs/stripe/planner/raster_plan.h"
#include "procs/stripe/planner/scan_sequencer.h"

namespace ephor::stripe {

// Where the plan task's answers go: the bus in main.cc, the checks in the
// fuzz target. Each message comes with its utime set, a goal and a capture
// with the sequencer's action it was made of.
class PlanOutputs {
 public:
  virtual ~PlanOutputs() = default;
  virtual void goal(const GoalAction& action, arm_goal_t m) = 0;
  virtual void capture(const CaptureAction& action, stripe_capture_t m) = 0;
  virtual void scan(stripe_scan_t m) = 0;
};

struct PlanTaskConfig {
  RasterSpec spec;
  double speed_mm_s = 0.0;  // asked of the arm; 0 = its default
  int scans = 1;            // then finished; 0 = scan again and again
  double pause_s = 3.0;     // between scans
  // The raster from the arm's joints (plan_raster() with the work cell and
  // calibration); throws PlanError when it cannot be scanned from there.
  std::function<RasterPlan(const arm::Joints& from)> plan;
  // The wall clock, us: the messages' utime and each scan's id.
  std::function<int64_t()> wall_us;
  // For the summary and the log: the robot and its calibration.
  int robot_seed = 0;
  std::string calibration_name;      // the file, or "drawing"
  std::string calibration_measured;  // how it was measured (one line)
  std::string summary_path;          // each scan's summary written here ("" = not written)
};

class PlanTask {
 public:
  // Goal and request ids count up from first_id (main.cc: the wall clock at
  // its start, so that a restarted planner's ids never repeat the old one's:
  // the arm would log the same goal twice, the camera answer an old request
  // with its old image).
  PlanTask(PlanTaskConfig config, PlanOutputs& out, int64_t first_id);

  // One run of the task at t_s: the events since the last run in the order
  // they came, the newest arm joints (nullopt before the first ARM_STATE)
  // and whether the arm reports moving. Does nothing once finished().
  void run(double t_s, const std::vector<PlanEvent>& events,
           const std::optional<arm::Joints>& arm_q, bool arm_moving);

  bool finished() const { return finished_; }
  // 0, or 1 when a scan failed or could not be planned.
  int exit_code() const { return exit_code_; }
  // The scan in hand (nullptr before the first) and its plan.
  const ScanSequencer* sequencer() const { return seq_ ? &*seq_ : nullptr; }
  const RasterPlan& plan() const { return plan_; }
  // The last ended scan's summary (null before one ends).
  const nlohmann::json& summary() const { return summary_; }

 private:
  bool new_scan(double t_s, const arm::Joints& from);
  void act(const SequencerActions& a, double t_s);
  void publish_scan(double t_s);
  void finish_scan(double t_s);

  PlanTaskConfig config_;
  PlanOutputs& out_;
  std::optional<ScanSequencer> seq_;
  RasterPlan plan_;
  int64_t scan_id_ = 0, next_goal_, next_request_;
  int last_goal_stripe_ = -1, last_retaken_ = 0, last_range_losses_ = 0, scans_done_ = 0;
  double last_status_s_ = 0.0, pause_until_s_ = 0.0;
  ScanCpu cpu_;
  CloudEvent last_cloud_{};
  nlohmann::json summary_;
  bool finished_ = false;
  int exit_code_ = 0;
};

}  // namespace ephor::stripe
