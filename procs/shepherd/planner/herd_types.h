#pragma once
// Plain structs the shepherd's planners take and return. No LCM here: the
// thin main (main.cc) converts shepherd_objects_t / arm_state_t / motion_done_t to
// these and Goal to arm_goal_t.
//
// Frame: field frame F (common/geometry/workcell.h): mm, origin at the field
// corner shown bottom-left in the image, x along the long side, y along the
// short side. Velocities in mm/s, times in s, angles in rad from +x towards +y.

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "common/geometry/workcell.h"

namespace ephor::planner {

using JointAngles = std::array<double, 6>;  // rad, PUMA 560 joint order (arm_state_t.q)

enum class SheepState { kVisible, kObscured, kDead };

// One tracked sheep as the world model reports it (shepherd_object_t).
struct Sheep {
  int id = -1;
  double x_mm = 0.0;  // centre of the sheep's mark, F
  double y_mm = 0.0;
  double vx_mm_s = 0.0;  // filtered velocity, F
  double vy_mm_s = 0.0;
  SheepState state = SheepState::kVisible;
};

// What the planner assumes about the arm: where its tool tip is now and how
// fast it moves. The paper's planner "has access to the arm speed constant
// allowing it to estimate how long a requested move will take" (section 5).
struct ArmModel {
  double x_mm = 0.0;  // tool tip in F
  double y_mm = 0.0;
  bool lowered = false;       // true when the tip is in (or near) the object plane
  double speed_mm_s = 300.0;  // end-effector speed cap
  // Elevation plane (z = 200 mm) to object plane (z = 30 mm): 170 mm at
  // 300 mm/s is 0.57 s, rounded up for acceleration.
  double lowering_time_s = 0.7;
  double raise_time_s = 0.7;
  // Per goal: planner -> comm -> arm round trip, acceleration and settling.
  // The paper's arm was "sometimes in error": this is the allowance for it.
  double overhead_s = 0.25;
  // The arm's joints (ARM_STATE), when known. With them the planner can tell
  // a point the arm reaches in its current configuration from one that needs
  // a configuration change (ArmConfiguration): joint 1's +-160 deg leaves a
  // wedge of the field to each configuration, and ephor-arm changes
  // configuration by a joint-space path of 12-14 s (measured on the full
  // system), not the straight line this model times.
  bool joints_known = false;
  JointAngles joints_rad{};
  double configuration_switch_s = 13.0;
  // A move whose straight line passes the column (closer than
  // PlannerConfig::tool_keepout_mm) is a joint-space path around it:
  // ephor-arm took 9.9 s for a 1.0 m move that the straight-line model
  // times at 3.4 s. Added when the joints are known.
  double column_detour_s = 5.0;
};

enum class Plane { kElevation, kObject };

// One arm goal, in F. The main converts (x, y) and theta to image
// coordinates with the calibration of `plane`.
struct Goal {
  int64_t goal_id = 0;  // increasing per planner instance
  Plane plane = Plane::kElevation;
  double x_mm = 0.0;
  double y_mm = 0.0;
  double theta_rad = 0.0;  // manipulator orientation in F (faces the field centre when saving)
  int target = -1;         // sheep id served, -1 = none (parking, raising with no target)
};

// Everything one planning job looks at: the newest objects and arm state.
struct Scene {
  double now_s = 0.0;  // monotonic time of this job, s (goal timeouts)
  std::vector<Sheep> sheep;
  ArmModel arm;
};

// Tunables shared by all planners. Defaults fit the simulated work cell
// (30 mm/s sheep, 229 x 89 mm bodies, 300 mm/s arm).
struct PlannerConfig {
  geometry::Workcell workcell;
  // An intercept (tool point and sheep centre) must lie this far inside the
  // field edge; a sheep is counted as escaped when its centre crosses it.
  double field_margin_mm = 10.0;
  // The tool is placed this far ahead of the sheep's centre along its path,
  // i.e. just behind its nose (half body length 114.5 mm): early, the sheep
  // walks into the lowered tool; late, the tool still lands on its body.
  double sheep_lead_mm = 60.0;
  double sheep_half_length_mm = 114.5;
  double sheep_half_width_mm = 44.5;
  // Another sheep whose predicted centre comes this close to an intercept
  // around the intercept time makes the intercept unusable (paper step 2).
  double clearance_mm = 120.0;
  // When every candidate's intercept lies on another sheep's path, save the
  // most urgent of them anyway instead of holding while they leave (two
  // sheep walking side by side would otherwise both escape; a touch only
  // turns a sheep toward the centre, so landing near a second one is
  // harmless in the simulator). false = the paper's rule strictly.
  bool last_resort_on_other_path = true;
  // A sheep whose velocity points within this angle of the field centre is
  // "already headed toward the center" and does not need saving.
  double heading_to_centre_rad = 0.5;
  // A sheep this close to the field centre does not need saving: turning it
  // "toward the centre" there gains nothing (it would cross the centre and
  // be a candidate again at once, starving sheep near the edge).
  double centre_zone_mm = 150.0;
  // Where the lowered tool sends a sheep (its orientation theta: the
  // simulated sheep, as the paper's, is turned the way the manipulator
  // faces). The paper sends it at the centre; the PUMA's pedestal stands
  // there, so such a sheep bounces straight back out to the edge it was
  // saved from. Instead the tool faces, within redirect_max_rad of the
  // centre (so the sheep still counts as headed toward it), the way the
  // sheep walks longest before the edge, the pedestal (its centre line
  // within redirect_clearance_mm of the column's axis: pedestal 70 mm + half
  // a body's width 44.5 mm + 20 mm) or another sheep's path
  // (FieldRules::redirect_heading). redirect_clearance_mm = 0: at the centre.
  double redirect_clearance_mm = 135.0;
  double redirect_max_rad = 0.4;
  double redirect_nominal_speed_mm_s = 8.0;  // for a sheep seen standing
  // Slower sheep are treated as stationary (never leave).
  double min_sheep_speed_mm_s = 3.0;
  // When a sheep leaves, for choosing whom to save and in what order: false,
  // along its straight line (the paper's step 1); true, also bouncing off
  // the pedestal and the other sheep as the simulated sheep do, stepped
  // bounce_horizon_s ahead (BouncePredictor): a sheep walking out that
  // another will turn back in is not saved, and the order is by the bounced
  // exits.
  bool predict_bounces = false;
  double bounce_horizon_s = 20.0;
  // Only sheep that leave within this time need saving "yet" (paper step 1).
  double save_horizon_s = std::numeric_limits<double>::infinity();
  // The PUMA stands on a pedestal at the field centre and cannot hold the
  // tool pointing down close to its own column: within about 340 mm of it in
  // the elevation plane (z = 200 mm) and 140 mm in the object plane (z =
  // 30 mm) there is no inverse kinematics solution (common/arm
  // reachable_tool_down; field_rules_test checks these radii against it).
  // Every point the tool is sent to lies outside tool_keepout_mm.
  double tool_keepout_mm = 360.0;
  // Where the arm waits when no sheep needs saving: the lower-right corner
  // of the image (x max, y min in F), pulled in so the PUMA reaches it.
  double park_x_mm = 1219.0 - 60.0;
  double park_y_mm = 60.0;
  // The way to the park position is sent in legs of at most this length, so
  // that a sheep needing saving on the way is seen after at most one leg (a
  // goal cannot be cancelled; the planner waits for its motion_done).
  double park_leg_mm = 150.0;
  // After reaching the intercept, a re-planned intercept farther than this
  // from the tool means another elevation move instead of lowering.
  double correction_tolerance_mm = 40.0;
  // While lowered: the sheep's path passing farther than this from the tool
  // triggers a correction in the object plane.
  double lateral_tolerance_mm = 30.0;
  int max_corrections = 3;
  // The lowered tool turns a sheep when the tip is within this of its body
  // (ephor-sim's touch_radius_mm). While the tool is down, the arm hides the
  // sheep's mark from the camera, so its new heading may not be seen: a
  // predicted body over the tool for touch_confirm_s counts as the touch.
  double touch_radius_mm = 15.0;
  double touch_confirm_s = 0.2;
  // A sheep just saved is not a candidate again for this long: the world
  // model's filtered velocity takes a few frames to show the turn.
  double resave_cooldown_s = 1.5;
  // How long the lowered tool waits for the sheep at most, s.
  double max_turn_wait_s = 30.0;
  // A goal without motion_done after factor * expected duration + slack is
  // treated as failed (comm already retries; this guards against loss).
  double goal_timeout_factor = 2.0;
  // The slack covers the arm's joint-space paths (up to ~14 s where the
  // straight-line estimate says 3 s): a goal timed out while the arm still
  // moves would be replaced mid-swing. Failures and lost commands are
  // reported by comm (retries, TIMEOUT) long before this guard fires.
  double goal_timeout_slack_s = 15.0;
  // After a failed goal the next waits failure_backoff_s, doubling with each
  // further consecutive failure up to failure_backoff_max_s.
  double failure_backoff_s = 0.25;
  double failure_backoff_max_s = 2.0;
  // A sheep whose intercept needs a configuration change of the arm is
  // passed over for one reachable as the arm is, while it would still leave
  // the field more than this after its (switched) intercept time, s.
  double switch_defer_slack_s = 6.0;
  // With the arm's joints known, an elevation move whose straight line
  // passes the column is sent as straight legs around it (waypoints),
  // instead of leaving ephor-arm a joint-space path of 4-13 s.
  bool column_waypoints = true;
  // Look-ahead planner: saves searched ahead, candidates considered, budget.
  int lookahead_depth = 3;
  int lookahead_max_candidates = 8;
  double lookahead_budget_s = 0.005;
};

// What a planner is doing, for shepherd_planner_status_t and the display.
struct PlannerStatus {
  std::string phase = "idle";  // idle, choosing, moving, verifying, lowering, turning, raising,
                               // parking, parked, holding
  int target = -1;
  double intercept_x_mm = 0.0;
  double intercept_y_mm = 0.0;
  double intercept_time_s = 0.0;  // from the job's time until the sheep reaches the intercept
  int num_candidates = 0;         // sheep needing saving this job
  int64_t goal_id = 0;            // newest goal sent
  int64_t goals_failed = 0;       // motion_done failures and timeouts
  int64_t goals_timed_out = 0;
  int64_t saves = 0;      // targets seen turned toward the centre while lowered
  int64_t bad_sheep = 0;  // sheep ignored for non-finite values
};

}  // namespace ephor::planner
