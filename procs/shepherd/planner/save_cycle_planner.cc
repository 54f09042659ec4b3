#include "procs/shepherd/planner/save_cycle_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

namespace ephor::planner {

namespace {

// The sheep's path relative to a point: distance ahead of the sheep's centre
// along its heading and signed distance to the left of it, mm.
struct PathOffset {
  double along_mm = 0.0;
  double lateral_mm = 0.0;
  double speed_mm_s = 0.0;
};

PathOffset offset_from_path(const Sheep& s, double x_mm, double y_mm) {
  PathOffset out;
  out.speed_mm_s = std::hypot(s.vx_mm_s, s.vy_mm_s);
  const double dx = x_mm - s.x_mm;
  const double dy = y_mm - s.y_mm;
  if (out.speed_mm_s < 1e-9) {
    out.along_mm = 0.0;
    out.lateral_mm = std::hypot(dx, dy);
    return out;
  }
  const double ux = s.vx_mm_s / out.speed_mm_s;
  const double uy = s.vy_mm_s / out.speed_mm_s;
  out.along_mm = dx * ux + dy * uy;
  out.lateral_mm = ux * dy - uy * dx;
  return out;
}

}  // namespace

SaveCyclePlanner::SaveCyclePlanner(const PlannerConfig& config)
    : rules_(config), arm_configuration_(config.workcell) {}

const char* SaveCyclePlanner::phase_name(Phase phase) {
  switch (phase) {
    case Phase::kChoosing:
      return "choosing";
    case Phase::kMoving:
      return "moving";
    case Phase::kVerifying:
      return "verifying";
    case Phase::kLowering:
      return "lowering";
    case Phase::kTurning:
      return "turning";
    case Phase::kCorrecting:
      return "correcting";
    case Phase::kRaising:
      return "raising";
    case Phase::kParking:
      return "parking";
    case Phase::kParked:
      return "parked";
    case Phase::kHolding:
      return "holding";
  }
  return "unknown";
}

void SaveCyclePlanner::set_phase(Phase phase) {
  phase_ = phase;
  status_.phase = phase_name(phase);
}

double SaveCyclePlanner::lowering_delay_s(const ArmModel& arm) const {
  // Two goals (the move, then the lowering) each pay the overhead.
  return arm.lowering_time_s + 2.0 * arm.overhead_s;
}

double SaveCyclePlanner::switch_time_s(const ArmModel& arm, double x_mm, double y_mm) const {
  if (!arm.joints_known) return 0.0;
  const double theta = std::atan2(rules_.centre_y_mm() - y_mm, rules_.centre_x_mm() - x_mm);
  const double z = config().workcell.elevation_plane_z_mm;
  if (arm_configuration_.needs_switch(arm.joints_rad, x_mm, y_mm, z, theta)) {
    return arm.configuration_switch_s;
  }
  if (passes_column(arm.x_mm, arm.y_mm, x_mm, y_mm)) return arm.column_detour_s;
  // Both ends in this configuration, but the line between them crosses joint
  // 1's wedge: ephor-arm goes round by a joint-space path as long as a switch.
  if (arm_configuration_.line_needs_detour(arm.joints_rad, x_mm, y_mm, z, theta)) {
    return arm.configuration_switch_s;
  }
  return 0.0;
}

bool SaveCyclePlanner::passes_column(double ax, double ay, double x_mm, double y_mm) const {
  // Closest approach of the straight tool path to the column axis, mm.
  const double bx = config().workcell.base_x_mm;
  const double by = config().workcell.base_y_mm;
  const double dx = x_mm - ax;
  const double dy = y_mm - ay;
  const double len2 = dx * dx + dy * dy;
  const double t =
      len2 > 1e-9 ? std::clamp(((bx - ax) * dx + (by - ay) * dy) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(ax + t * dx - bx, ay + t * dy - by) < config().tool_keepout_mm;
}

std::optional<std::pair<double, double>> SaveCyclePlanner::column_waypoint(const ArmModel& arm,
                                                                           double x_mm,
                                                                           double y_mm) const {
  if (!arm.joints_known || arm.lowered || !passes_column(arm.x_mm, arm.y_mm, x_mm, y_mm)) {
    return std::nullopt;
  }
  const double z = config().workcell.elevation_plane_z_mm;
  const double cx = rules_.centre_x_mm();
  const double cy = rules_.centre_y_mm();
  if (arm_configuration_.needs_switch(arm.joints_rad, x_mm, y_mm, z,
                                      std::atan2(cy - y_mm, cx - x_mm))) {
    return std::nullopt;  // a configuration change: ephor-arm's joint-space path it is
  }
  const double bx = config().workcell.base_x_mm;
  const double by = config().workcell.base_y_mm;
  const double a0 = std::atan2(arm.y_mm - by, arm.x_mm - bx);
  const double d = std::remainder(std::atan2(y_mm - by, x_mm - bx) - a0, 2.0 * std::numbers::pi);
  const double other_way = d > 0.0 ? d - 2.0 * std::numbers::pi : d + 2.0 * std::numbers::pi;
  // Round the column the way joint 1 turns to the goal: the other way
  // crosses the wedge the configuration cannot reach, so a leg that way
  // would leave a next leg (or ephor-arm) the whole way back round. Without
  // a turn (the goal out of reach as the arm is): the short way, then the
  // long way.
  std::vector<double> directions{d, other_way};
  if (const auto turn = arm_configuration_.joint1_turn_rad(arm.joints_rad, x_mm, y_mm, z,
                                                           std::atan2(cy - y_mm, cx - x_mm))) {
    directions = {(*turn > 0.0) == (d > 0.0) ? d : other_way};
  }
  for (const double dir : directions) {
    for (double step_deg = 80.0; step_deg >= 20.0; step_deg -= 10.0) {
      const double step =
          std::copysign(std::min(std::abs(dir), step_deg * std::numbers::pi / 180.0), dir);
      const double a = a0 + step;
      // As far out as the field allows (at most 520 mm), so that the chord
      // from the tool stays clear of the column.
      for (double r = 520.0; r >= config().tool_keepout_mm + 20.0; r -= 20.0) {
        const double wx = bx + r * std::cos(a);
        const double wy = by + r * std::sin(a);
        if (!rules_.usable_point(wx, wy)) continue;
        if (passes_column(arm.x_mm, arm.y_mm, wx, wy)) break;  // smaller r only gets closer
        const double theta = std::atan2(cy - wy, cx - wx);
        // A leg that needs a configuration change, or whose line crosses
        // joint 1's wedge, would cost the 12-15 s the legs are there to save.
        if (!arm::reachable_tool_down(config().workcell, wx, wy, z, theta) ||
            arm_configuration_.needs_switch(arm.joints_rad, wx, wy, z, theta) ||
            arm_configuration_.line_needs_detour(arm.joints_rad, wx, wy, z, theta)) {
          continue;
        }
        return std::make_pair(wx, wy);
      }
    }
  }
  return std::nullopt;
}

bool SaveCyclePlanner::on_motion_done(int64_t goal_id, bool succeeded) {
  if (!outstanding_ || outstanding_->goal.goal_id != goal_id) return false;
  outstanding_.reset();
  last_result_ = succeeded;
  if (succeeded) {
    consecutive_failures_ = 0;
  } else {
    ++status_.goals_failed;
    ++consecutive_failures_;
    backoff_pending_ = true;
  }
  return true;
}

std::optional<Goal> SaveCyclePlanner::plan(const Scene& raw) {
  if (!std::isfinite(raw.now_s) || !std::isfinite(raw.arm.x_mm) || !std::isfinite(raw.arm.y_mm) ||
      !(raw.arm.speed_mm_s > 0.0)) {
    return std::nullopt;  // nothing sensible to plan from; the main logs it
  }
  Scene scene;
  scene.now_s = raw.now_s;
  scene.arm = raw.arm;
  scene.sheep.reserve(raw.sheep.size());
  for (const Sheep& s : raw.sheep) {
    if (finite_sheep(s)) {
      scene.sheep.push_back(s);
    } else {
      ++status_.bad_sheep;
    }
  }
  if (outstanding_) {
    if (scene.now_s <= outstanding_->deadline_s) {
      status_.intercept_time_s = std::max(0.0, intercept_.t_s);
      return std::nullopt;  // keep waiting for motion_done; never more than one goal out
    }
    // No motion_done in time: treat as failed and replan from here.
    outstanding_.reset();
    ++status_.goals_failed;
    ++status_.goals_timed_out;
    ++consecutive_failures_;
    backoff_pending_ = true;
    last_result_ = false;
  }
  if (backoff_pending_) {
    // A failing arm (refusals, faults) must not be flooded with goals:
    // wait 0.25 s, 0.5 s, 1 s, ... (at most failure_backoff_max_s) after
    // consecutive failures before the next.
    backoff_pending_ = false;
    const double wait = std::min(
        config().failure_backoff_max_s,
        config().failure_backoff_s * std::pow(2.0, std::min(consecutive_failures_ - 1, 10)));
    retry_after_s_ = scene.now_s + wait;
  }
  if (scene.now_s < retry_after_s_) return std::nullopt;
  return step(scene);
}

std::optional<Goal> SaveCyclePlanner::step(const Scene& scene) {
  if (last_result_) {
    const bool done = *last_result_;
    last_result_.reset();
    switch (phase_) {
      case Phase::kMoving:
        set_phase(done ? Phase::kVerifying : Phase::kChoosing);
        break;
      case Phase::kLowering:
      case Phase::kCorrecting:
        if (!done) return raise(scene);  // the tool may be down: get it out of the way first
        if (phase_ == Phase::kLowering) {
          turn_deadline_s_ = -1.0;  // computed on the next look
          body_over_tool_since_s_ = -1.0;
        }
        set_phase(Phase::kTurning);
        break;
      case Phase::kRaising:
        if (!done && ++raise_failures_ < 2) return raise(scene);
        raise_failures_ = 0;
        set_phase(Phase::kChoosing);
        if (done && target_saved_ && parks_after_save()) {
          target_saved_ = false;
          target_ = -1;
          return park(scene);
        }
        break;
      case Phase::kParking:
        set_phase(Phase::kChoosing);  // the next leg, or a sheep to save
        break;
      default:
        set_phase(Phase::kChoosing);
        break;
    }
  }
  switch (phase_) {
    case Phase::kVerifying:
      return verify(scene);
    case Phase::kTurning:
      return watch_turn(scene);
    default:
      return start_over(scene);
  }
}

std::vector<int> SaveCyclePlanner::save_candidates(const Scene& scene) {
  // A saved sheep seen again (visible) is judged on its new velocity.
  for (const Sheep& s : scene.sheep) {
    if (s.state == SheepState::kVisible) unseen_since_save_.erase(s.id);
  }
  std::vector<int> out;
  for (int index : rules_.candidates_by_urgency(scene.sheep)) {
    const int id = scene.sheep[static_cast<size_t>(index)].id;
    if (unseen_since_save_.count(id) > 0) continue;
    const auto it = cooldown_until_s_.find(id);
    if (it == cooldown_until_s_.end() || scene.now_s >= it->second) out.push_back(index);
  }
  return out;
}

const Sheep* SaveCyclePlanner::find_target(const Scene& scene) const {
  for (const Sheep& s : scene.sheep) {
    if (s.id == target_ && s.state != SheepState::kDead) return &s;
  }
  return nullptr;
}

std::optional<Goal> SaveCyclePlanner::start_over(const Scene& scene) {
  target_ = -1;
  corrections_ = 0;
  target_saved_ = false;
  if (scene.arm.lowered) return raise(scene);
  int candidates = 0;
  const auto chosen = choose(scene, &candidates);
  status_.num_candidates = candidates;
  if (chosen) {
    target_ = chosen->target;
    intercept_ = chosen->intercept;
    ignores_other_sheep_ = chosen->ignores_other_sheep;
    status_.target = target_;
    status_.intercept_x_mm = intercept_.x_mm;
    status_.intercept_y_mm = intercept_.y_mm;
    status_.intercept_time_s = intercept_.t_s;
    return send(scene, Plane::kElevation, intercept_.x_mm, intercept_.y_mm, intercept_.theta_rad,
                target_, Phase::kMoving);
  }
  status_.target = -1;
  if (candidates > 0) {
    set_phase(Phase::kHolding);  // sheep need saving but no intercept is usable now
    return std::nullopt;
  }
  // Nobody needs saving: keep the arm out of the camera's way.
  return park(scene);
}

std::optional<Goal> SaveCyclePlanner::park(const Scene& scene) {
  const double px = config().park_x_mm;
  const double py = config().park_y_mm;
  const double dist = std::hypot(px - scene.arm.x_mm, py - scene.arm.y_mm);
  if (dist <= 15.0) {
    set_phase(Phase::kParked);
    return std::nullopt;
  }
  const double leg = std::min(1.0, std::max(config().park_leg_mm, 1.0) / dist);
  double x = scene.arm.x_mm + leg * (px - scene.arm.x_mm);
  double y = scene.arm.y_mm + leg * (py - scene.arm.y_mm);
  // A leg ending next to the column would be out of the arm's reach: push it
  // out (the arm finds its own way around the column between legs).
  const double bx = config().workcell.base_x_mm;
  const double by = config().workcell.base_y_mm;
  const double r = std::hypot(x - bx, y - by);
  const double r_min = config().tool_keepout_mm + 10.0;
  if (r < r_min) {
    const double ux = r > 1e-6 ? (x - bx) / r : 0.0;
    const double uy = r > 1e-6 ? (y - by) / r : -1.0;
    x = bx + r_min * ux;
    y = by + r_min * uy;
  }
  const double theta = std::atan2(rules_.centre_y_mm() - py, rules_.centre_x_mm() - px);
  // A leg that needs a configuration change, or whose line crosses joint
  // 1's wedge, is a joint-space path of 12-15 s during which no sheep can be
  // saved. Unless every sheep stays on the field well beyond that, the arm
  // waits where it is instead (the stand-in's seed 2 lost a sheep to a 15 s
  // leg towards the corner; a lone sheep, just turned, has the time).
  double soonest_exit_s = std::numeric_limits<double>::infinity();
  for (const Sheep& s : scene.sheep)
    soonest_exit_s = std::min(soonest_exit_s, rules_.time_to_boundary(s));
  const double z = config().workcell.elevation_plane_z_mm;
  if (scene.arm.joints_known && soonest_exit_s < scene.arm.configuration_switch_s + 10.0 &&
      (arm_configuration_.needs_switch(scene.arm.joints_rad, x, y, z, theta) ||
       arm_configuration_.line_needs_detour(scene.arm.joints_rad, x, y, z, theta))) {
    set_phase(Phase::kParked);
    return std::nullopt;
  }
  return send(scene, Plane::kElevation, x, y, theta, -1, Phase::kParking);
}

std::optional<Intercept> SaveCyclePlanner::replan_at_intercept(const Scene& scene,
                                                               const Sheep& target) {
  return InterceptSolver::solve(scene.arm, target, config().sheep_lead_mm,
                                scene.arm.lowering_time_s + scene.arm.overhead_s,
                                rules_.centre_x_mm(), rules_.centre_y_mm());
}

std::optional<Goal> SaveCyclePlanner::verify(const Scene& scene) {
  const Sheep* target = find_target(scene);
  if (target == nullptr || rules_.heading_to_centre(*target)) return start_over(scene);
  const double delay = scene.arm.lowering_time_s + scene.arm.overhead_s;
  std::optional<Intercept> lower_at;
  // The arm got there early and the sheep will walk under it: lower here,
  // shifted onto the sheep's path.
  const PathOffset off = offset_from_path(*target, scene.arm.x_mm, scene.arm.y_mm);
  if (off.speed_mm_s >= config().min_sheep_speed_mm_s &&
      std::abs(off.lateral_mm) <= config().correction_tolerance_mm &&
      off.along_mm - off.speed_mm_s * delay >=
          config().sheep_lead_mm - config().sheep_half_length_mm) {
    Intercept ic;
    const double ux = target->vx_mm_s / off.speed_mm_s;
    const double uy = target->vy_mm_s / off.speed_mm_s;
    ic.x_mm = target->x_mm + off.along_mm * ux;
    ic.y_mm = target->y_mm + off.along_mm * uy;
    ic.t_s = std::max(delay, (off.along_mm - config().sheep_lead_mm) / off.speed_mm_s);
    ic.sheep_x_mm = target->x_mm + target->vx_mm_s * ic.t_s;
    ic.sheep_y_mm = target->y_mm + target->vy_mm_s * ic.t_s;
    ic.theta_rad = std::atan2(rules_.centre_y_mm() - ic.y_mm, rules_.centre_x_mm() - ic.x_mm);
    if (rules_.usable_point(ic.x_mm, ic.y_mm)) lower_at = ic;
  }
  if (!lower_at) {
    // The arm was slower (or the sheep turned a little): re-plan from here.
    const auto ic = replan_at_intercept(scene, *target);
    if (!ic || !rules_.intercept_in_field(*ic, *target)) return start_over(scene);
    if (std::hypot(ic->x_mm - scene.arm.x_mm, ic->y_mm - scene.arm.y_mm) >
        config().correction_tolerance_mm) {
      if (corrections_ >= config().max_corrections) return start_over(scene);
      ++corrections_;
      intercept_ = *ic;
      status_.intercept_x_mm = ic->x_mm;
      status_.intercept_y_mm = ic->y_mm;
      status_.intercept_time_s = ic->t_s;
      return send(scene, Plane::kElevation, ic->x_mm, ic->y_mm, ic->theta_rad, target_,
                  Phase::kMoving);
    }
    lower_at = ic;
  }
  // Step 3's re-check: no other sheep under the arm while it is down.
  if (checks_other_sheep() && !ignores_other_sheep_ &&
      rules_.other_sheep_near(scene.sheep, target_, lower_at->x_mm, lower_at->y_mm, 0.0,
                              lower_at->t_s + scene.arm.raise_time_s) >= 0) {
    return start_over(scene);
  }
  intercept_ = *lower_at;
  status_.intercept_x_mm = lower_at->x_mm;
  status_.intercept_y_mm = lower_at->y_mm;
  status_.intercept_time_s = lower_at->t_s;
  return send(scene, Plane::kObject, lower_at->x_mm, lower_at->y_mm, lower_at->theta_rad, target_,
              Phase::kLowering);
}

std::optional<Goal> SaveCyclePlanner::watch_turn(const Scene& scene) {
  const Sheep* target = find_target(scene);
  if (target == nullptr) return raise(scene);  // gone (escaped, dead, lost): free the arm
  const auto saved = [&] {
    ++status_.saves;
    target_saved_ = true;
    cooldown_until_s_[target_] = scene.now_s + config().resave_cooldown_s;
    if (target->state != SheepState::kVisible) unseen_since_save_.insert(target_);
    body_over_tool_since_s_ = -1.0;
    return raise(scene);
  };
  // Turned by the touch (or on its own): the save is done.
  if (rules_.heading_to_centre(*target)) return saved();
  const PathOffset off = offset_from_path(*target, scene.arm.x_mm, scene.arm.y_mm);
  // The (possibly dead-reckoned, the arm hiding it) body over the tool for
  // long enough: touched.
  if (std::abs(off.along_mm) <= config().sheep_half_length_mm + config().touch_radius_mm &&
      std::abs(off.lateral_mm) <= config().sheep_half_width_mm + config().touch_radius_mm) {
    if (body_over_tool_since_s_ < 0.0) body_over_tool_since_s_ = scene.now_s;
    if (scene.now_s - body_over_tool_since_s_ >= config().touch_confirm_s) return saved();
  } else {
    body_over_tool_since_s_ = -1.0;
  }
  if (turn_deadline_s_ < 0.0) {
    // Wait until the whole body has passed the tool, plus a second.
    double wait = 2.0;
    if (off.speed_mm_s >= config().min_sheep_speed_mm_s) {
      wait = std::max(0.0, off.along_mm + config().sheep_half_length_mm) / off.speed_mm_s + 1.0;
    }
    turn_deadline_s_ = scene.now_s + std::min(wait, config().max_turn_wait_s);
  }
  if (scene.now_s > turn_deadline_s_) return raise(scene);
  // At the paper's 8 mm/s a lowered tool may wait 20 s for its sheep to walk
  // into it; another sheep must not walk off the field meanwhile (issue 13:
  // the stand-in lost sheep exactly so). The target is chosen again later.
  if (another_sheep_needs_the_arm(scene, turn_deadline_s_ - scene.now_s)) return raise(scene);
  if (off.speed_mm_s < config().min_sheep_speed_mm_s) return std::nullopt;
  if (off.along_mm < -(config().sheep_half_length_mm + 30.0)) return raise(scene);  // passed by
  // Paper's single-sheep planner: "the position and orientation of the
  // manipulator are corrected to compensate for slight changes".
  if (std::abs(off.lateral_mm) > config().lateral_tolerance_mm && off.along_mm > 0.0 &&
      corrections_ < config().max_corrections) {
    const double ux = target->vx_mm_s / off.speed_mm_s;
    const double uy = target->vy_mm_s / off.speed_mm_s;
    const double x = target->x_mm + off.along_mm * ux;
    const double y = target->y_mm + off.along_mm * uy;
    if (rules_.usable_point(x, y)) {
      ++corrections_;
      return send(scene, Plane::kObject, x, y,
                  std::atan2(rules_.centre_y_mm() - y, rules_.centre_x_mm() - x), target_,
                  Phase::kCorrecting);
    }
  }
  return std::nullopt;
}

bool SaveCyclePlanner::another_sheep_needs_the_arm(const Scene& scene, double wait_left_s) const {
  const ArmModel& arm = scene.arm;
  // Slack for what the straight-line model does not time: the world model's
  // lag in seeing the sheep, a correction, the goal round trips.
  constexpr double kSlackS = 2.0;
  for (int index : rules_.candidates_by_urgency(scene.sheep)) {
    const Sheep& s = scene.sheep[static_cast<size_t>(index)];
    if (s.id == target_) continue;
    const double leaves_in_s = rules_.time_to_boundary(s);
    if (!std::isfinite(leaves_in_s)) continue;
    // Raise, cross to where the sheep is now, lower: the arm's time to it.
    const double reach_s = arm.raise_time_s + arm.lowering_time_s + 3.0 * arm.overhead_s +
                           std::hypot(s.x_mm - arm.x_mm, s.y_mm - arm.y_mm) / arm.speed_mm_s;
    const bool lost_if_waiting = leaves_in_s < wait_left_s + reach_s + kSlackS;
    const bool savable_now = leaves_in_s > reach_s;
    if (lost_if_waiting && savable_now) return true;
  }
  return false;
}

std::optional<Goal> SaveCyclePlanner::raise(const Scene& scene) {
  return send(
      scene, Plane::kElevation, scene.arm.x_mm, scene.arm.y_mm,
      std::atan2(rules_.centre_y_mm() - scene.arm.y_mm, rules_.centre_x_mm() - scene.arm.x_mm),
      target_, Phase::kRaising);
}

std::optional<Goal> SaveCyclePlanner::send(const Scene& scene, Plane plane, double x_mm,
                                           double y_mm, double theta_rad, int target, Phase next) {
  // ephor-arm goes past its column by a joint-space path of 4-13 s; two or
  // three straight legs around it take a fraction of that. The leg ends at a
  // waypoint; verify() then re-plans from there (the next leg, or lowering).
  bool waypoint = false;
  if (plane == Plane::kElevation && config().column_waypoints) {
    if (const auto wp = column_waypoint(scene.arm, x_mm, y_mm)) {
      x_mm = wp->first;
      y_mm = wp->second;
      theta_rad = std::atan2(rules_.centre_y_mm() - y_mm, rules_.centre_x_mm() - x_mm);
      waypoint = true;
    }
  }
  // Serving a sheep: the tool faces where the touch will send it (past the
  // pedestal), already on the way there so the wrist need not turn when
  // lowering.
  if (target >= 0 && !waypoint)
    theta_rad = rules_.redirect_heading(x_mm, y_mm, scene.sheep, target);
  Goal goal;
  goal.goal_id = next_goal_id_++;
  goal.plane = plane;
  goal.x_mm = x_mm;
  goal.y_mm = y_mm;
  goal.theta_rad = theta_rad;
  goal.target = target;
  const ArmModel& arm = scene.arm;
  double expected = std::hypot(x_mm - arm.x_mm, y_mm - arm.y_mm) / arm.speed_mm_s + arm.overhead_s;
  if (plane == Plane::kObject && !arm.lowered) expected += arm.lowering_time_s;
  if (plane == Plane::kElevation && arm.lowered) expected += arm.raise_time_s;
  // A configuration change takes 12-14 s: without it here the goal would time
  // out (and be replaced) while the arm is still swinging over.
  if (plane == Plane::kElevation) expected += switch_time_s(arm, x_mm, y_mm);
  outstanding_ = Outstanding{
      goal, scene.now_s + config().goal_timeout_factor * expected + config().goal_timeout_slack_s};
  status_.goal_id = goal.goal_id;
  set_phase(next);
  return goal;
}

}  // namespace ephor::planner
