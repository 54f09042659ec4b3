#pragma once
// ephor-rambo-planner's handlers and plan task, out of main.cc so that the
// fuzz target planner_task_fuzz.cc runs what the process runs:
// RAMBO_PREDICTION as the motion (motion_from_message), RAMBO_INDICATOR as
// the diodes tagged, ARM_STATE as the arm's joints, and one planning period
// (TaggingPlanner's order and goal, the reaching trajectory with section 8's
// re-planning, the point-to-point goal's resend rule, the return to the
// viewing pose when the prediction is stale) into the ARM_GOAL to send and
// the RAMBO_PLAN to publish. Not thread-safe: main.cc holds its mutex
// around every call.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/arm/puma560.h"
#include "common/rambo/rambo_cell.h"
#include "common/rambo/tagging_planner.h"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/rambo_indicator_t.hpp"
#include "ephor/rambo_plan_t.hpp"
#include "ephor/rambo_prediction_t.hpp"

namespace ephor::rambo {

// The process's flags (their defaults).
struct PlannerTaskOptions {
  int diodes = 4;  // the cell's first N diodes are tagged
  TaggingOptions tagging;
  double max_prediction_age_s = 3.0;        // no goals from an older polynomial prediction, s
  double max_rigid_prediction_age_s = 8.0;  // nor from an older rigid-body one, s
  double arrive_rad = 0.03;      // the arm is at its goal within this: refresh it every period
  double resend_rad = 0.1;       // before that, send again only when it moved this far
  bool reach_trajectory = true;  // --reach trajectory (else point-to-point joint goals)
  double limit_fraction = 0.8;   // of the joint speed and acceleration limits
};

class PlannerTask {
 public:
  // run_id: the run's start (wall clock, us), so that goal ids stay unique
  // across restarts.
  PlannerTask(const RamboCell& cell, const PlannerTaskOptions& options, int64_t run_id);

  // RAMBO_PREDICTION: false (counted as bad, `why` set) when a fitted one
  // cannot be read; one not fitted is ignored (true).
  bool on_prediction(const rambo_prediction_t& m, std::string* why);
  // RAMBO_INDICATOR: false (counted as bad) when it is not for our diodes.
  bool on_indicator(const rambo_indicator_t& m);
  // ARM_STATE: ignored unless its joints and speeds are finite.
  void on_arm_state(const arm_state_t& m);

  struct Period {
    std::optional<arm_goal_t> goal;  // to ARM_GOAL, when one is sent
    rambo_plan_t plan;               // to RAMBO_PLAN, every period
  };
  // One planning period. clock: the wall clock (us), read as the task
  // reads it (at its start, before a reaching trajectory, for the goal's
  // utime).
  Period period(const std::function<int64_t()>& clock);

  // The joint limits the planner plans within (the PUMA's; reaching
  // trajectories use limit_fraction of its speeds and accelerations).
  const arm::JointLimits& limits() const { return arm_.limits(); }
  int64_t goals() const { return goals_; }
  int64_t trajectories() const { return trajectories_; }
  int64_t replans() const { return replans_; }
  int64_t bad() const { return bad_; }

 private:
  const RamboCell& cell_;
  PlannerTaskOptions options_;
  TaggingPlanner planner_;
  arm::Puma560 arm_;
  int64_t run_id_;
  std::optional<FittedMotion> motion_;
  int64_t motion_utime_ = 0;
  std::optional<arm::Joints> q_now_, qd_now_;
  int64_t state_utime_ = 0;  // of q_now_, qd_now_
  std::vector<bool> tagged_;
  // The reaching trajectory sent last: its diode and when it ends (wall
  // clock, us); none is sent while it runs.
  int trajectory_task_ = -2;
  int64_t trajectory_end_utime_ = 0, trajectory_land_utime_ = 0, trajectory_motion_utime_ = 0;
  std::optional<TaggingTrajectory> sent_trajectory_;  // the last reaching trajectory sent
  int last_task_ = -2, sent_task_ = -2;
  std::optional<arm::Joints> sent_goal_;
  std::string last_status_;
  std::vector<int> logged_order_{-1};
  bool looking_ = false;  // sent back to the viewing pose since the prediction went stale
  int64_t goals_ = 0, trajectories_ = 0, trajectory_failures_ = 0, replans_ = 0, bad_ = 0;
};

}  // namespace ephor::rambo
