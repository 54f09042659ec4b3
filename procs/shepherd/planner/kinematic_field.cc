#include "procs/shepherd/planner/kinematic_field.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ephor::planner {

KinematicField::KinematicField(const KinematicFieldConfig& config)
    : config_(config),
      rng_(config.seed),
      tool_x_(config.start_x_mm),
      tool_y_(config.start_y_mm),
      tool_z_(config.workcell.elevation_plane_z_mm) {
  if (config_.arm_motion) step_arm_motion(0.0);  // the tool is where the arm is
  for (int i = 0; i < config_.sheep; ++i) {
    SimSheep s{};
    spawn_inside(s);
    sheep_.push_back(s);
  }
}

KinematicField::KinematicField(const KinematicFieldConfig& config,
                               const std::vector<Sheep>& initial)
    : config_(config),
      rng_(config.seed),
      tool_x_(config.start_x_mm),
      tool_y_(config.start_y_mm),
      tool_z_(config.workcell.elevation_plane_z_mm) {
  if (config_.arm_motion) step_arm_motion(0.0);
  for (const Sheep& in : initial) {
    SimSheep s{};
    s.id = in.id;
    s.x = in.x_mm;
    s.y = in.y_mm;
    s.heading = std::atan2(in.vy_mm_s, in.vx_mm_s);
    s.speed = std::hypot(in.vx_mm_s, in.vy_mm_s);
    next_id_ = std::max(next_id_, in.id + 1);
    sheep_.push_back(s);
  }
}

void KinematicField::spawn_inside(SimSheep& s) {
  const auto& w = config_.workcell;
  const double m = config_.start_margin_mm;
  std::uniform_real_distribution<double> ux(m, w.field_length_mm - m);
  std::uniform_real_distribution<double> uy(m, w.field_width_mm - m);
  std::uniform_real_distribution<double> uh(-std::numbers::pi, std::numbers::pi);
  std::uniform_real_distribution<double> us(1.0 - config_.sheep_speed_jitter,
                                            1.0 + config_.sheep_speed_jitter);
  s.id = next_id_++;
  // With the pedestal, not on it (ephor-sim keeps a body length clear of it).
  const double clear_mm = config_.workcell.pedestal_radius_mm + config_.sheep_half_length_mm + 10.0;
  do {
    s.x = ux(rng_);
    s.y = uy(rng_);
  } while (config_.pedestal && std::hypot(s.x - w.base_x_mm, s.y - w.base_y_mm) < clear_mm);
  s.heading = uh(rng_);
  s.speed = config_.sheep_speed_mm_s * us(rng_);
  s.on_field = true;
}

void KinematicField::spawn_at_edge(SimSheep& s) {
  const auto& w = config_.workcell;
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::uniform_real_distribution<double> spread(-1.0, 1.0);
  std::uniform_real_distribution<double> us(1.0 - config_.sheep_speed_jitter,
                                            1.0 + config_.sheep_speed_jitter);
  const double inset = 5.0;
  const int side = static_cast<int>(u01(rng_) * 4.0) % 4;
  // Away from the corners, heading inwards, so a re-entering sheep does not
  // leave again at once.
  const auto along = [&](double length) { return 150.0 + u01(rng_) * (length - 300.0); };
  double inward = 0.0;
  switch (side) {
    case 0:
      s.x = inset;
      s.y = along(w.field_width_mm);
      inward = 0.0;
      break;
    case 1:
      s.x = w.field_length_mm - inset;
      s.y = along(w.field_width_mm);
      inward = std::numbers::pi;
      break;
    case 2:
      s.x = along(w.field_length_mm);
      s.y = inset;
      inward = std::numbers::pi / 2.0;
      break;
    default:
      s.x = along(w.field_length_mm);
      s.y = w.field_width_mm - inset;
      inward = -std::numbers::pi / 2.0;
      break;
  }
  s.id = next_id_++;
  s.heading = inward + spread(rng_) * config_.entry_angle_rad;
  s.speed = config_.sheep_speed_mm_s * us(rng_);
  s.on_field = true;
}

void KinematicField::send(const Goal& goal) {
  if (goal_) done_.emplace_back(goal_->goal_id, false);
  goal_ = goal;
  goal_start_s_ = now_s_ + config_.goal_latency_s;
  goal_started_ = false;
}

void KinematicField::step_arm_motion(double dt) {
  ArmMotion& arm = *config_.arm_motion;
  if (goal_ && now_s_ >= goal_start_s_ && !goal_started_) {
    const auto& w = config_.workcell;
    const double gz = goal_->plane == Plane::kObject ? w.object_plane_z_mm : w.elevation_plane_z_mm;
    goal_started_ = true;
    tool_theta_ = goal_->theta_rad;
    if (!arm.start(goal_->x_mm, goal_->y_mm, gz, goal_->theta_rad)) {
      done_.emplace_back(goal_->goal_id, false);
      goal_.reset();
    }
  }
  const bool ended = arm.step(dt);
  if (goal_ && goal_started_ && ended) {
    done_.emplace_back(goal_->goal_id, true);
    goal_.reset();
  }
  const auto tool = arm.tool_mm();
  tool_x_ = tool[0];
  tool_y_ = tool[1];
  tool_z_ = tool[2];
}

std::vector<std::pair<int64_t, bool>> KinematicField::take_done() {
  std::vector<std::pair<int64_t, bool>> out;
  out.swap(done_);
  return out;
}

void KinematicField::step(double dt) {
  const auto& w = config_.workcell;
  now_s_ += dt;
  if (config_.arm_motion) {
    step_arm_motion(dt);
  } else if (goal_ && now_s_ >= goal_start_s_) {
    // Arm: straight line at its speed cap towards the goal.
    tool_theta_ = goal_->theta_rad;
    const double gz = goal_->plane == Plane::kObject ? w.object_plane_z_mm : w.elevation_plane_z_mm;
    const double dx = goal_->x_mm - tool_x_;
    const double dy = goal_->y_mm - tool_y_;
    const double dz = gz - tool_z_;
    const double dist = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double reach = config_.arm_speed_mm_s * dt;
    if (dist <= reach) {
      tool_x_ = goal_->x_mm;
      tool_y_ = goal_->y_mm;
      tool_z_ = gz;
      done_.emplace_back(goal_->goal_id, true);
      goal_.reset();
    } else {
      tool_x_ += dx / dist * reach;
      tool_y_ += dy / dist * reach;
      tool_z_ += dz / dist * reach;
    }
  }
  const bool lowered = tool_z_ <= w.object_plane_z_mm + 1.0;
  for (SimSheep& s : sheep_) {
    if (!s.on_field) {
      if (now_s_ >= s.respawn_at_s) spawn_at_edge(s);
      continue;
    }
    s.x += s.speed * std::cos(s.heading) * dt;
    s.y += s.speed * std::sin(s.heading) * dt;
    if (!w.inside_field(s.x, s.y)) {
      ++escapes_;
      s.on_field = false;
      s.respawn_at_s = now_s_ + config_.respawn_s;
      continue;
    }
    // Touch: the tool tip inside the body rectangle (grown by the tool radius).
    bool inside = false;
    if (lowered) {
      const double dx = tool_x_ - s.x;
      const double dy = tool_y_ - s.y;
      const double along = dx * std::cos(s.heading) + dy * std::sin(s.heading);
      const double across = -dx * std::sin(s.heading) + dy * std::cos(s.heading);
      inside = std::abs(along) <= config_.sheep_half_length_mm + config_.tool_radius_mm &&
               std::abs(across) <= config_.sheep_half_width_mm + config_.tool_radius_mm;
    }
    if (inside && !s.touched_now) {
      s.old_heading = s.heading;
      s.turned_at_s = now_s_;
      s.heading = config_.touch_turns_along_tool
                      ? tool_theta_
                      : std::atan2(w.centre_y_mm() - s.y, w.centre_x_mm() - s.x);
      ++touches_;
    }
    s.touched_now = inside;
    const bool hidden = lowered && config_.hide_radius_mm > 0.0 &&
                        std::hypot(tool_x_ - s.x, tool_y_ - s.y) < config_.hide_radius_mm;
    if (!hidden) {
      s.hidden_since_s = -1.0;
    } else if (s.hidden_since_s < 0.0) {
      s.hidden_since_s = now_s_;
    }
  }
  bounce();
}

double KinematicField::extent(const SimSheep& s, double nx, double ny) const {
  const double c = std::cos(s.heading), sn = std::sin(s.heading);
  return config_.sheep_half_length_mm * std::abs(c * nx + sn * ny) +
         config_.sheep_half_width_mm * std::abs(-sn * nx + c * ny);
}

void KinematicField::reflect(SimSheep& s, double nx, double ny) {
  // World::bounce's rule: grazing contacts (under 5 % of the speed into the
  // obstacle) do not turn the sheep.
  constexpr double kMinApproach = 0.05;
  const double fx = std::cos(s.heading), fy = std::sin(s.heading);
  const double approach = fx * nx + fy * ny;
  if (approach <= kMinApproach) return;
  s.old_heading = s.heading;
  s.turned_at_s = now_s_;
  s.heading = std::atan2(fy - 2.0 * approach * ny, fx - 2.0 * approach * nx);
}

void KinematicField::bounce() {
  const auto& w = config_.workcell;
  for (size_t i = 0; i < sheep_.size(); ++i) {
    SimSheep& a = sheep_[i];
    if (!a.on_field) continue;
    if (config_.pedestal) {
      const double dx = w.base_x_mm - a.x, dy = w.base_y_mm - a.y;
      const double d = std::hypot(dx, dy);
      if (d > 1e-9 && d <= w.pedestal_radius_mm + extent(a, dx / d, dy / d)) {
        reflect(a, dx / d, dy / d);
      }
    }
    if (!config_.sheep_collisions) continue;
    for (size_t j = i + 1; j < sheep_.size(); ++j) {
      SimSheep& b = sheep_[j];
      if (!b.on_field) continue;
      const double dx = b.x - a.x, dy = b.y - a.y;
      const double d = std::hypot(dx, dy);
      if (d < 1e-9) continue;
      const double nx = dx / d, ny = dy / d;
      if (d > extent(a, nx, ny) + extent(b, nx, ny)) continue;
      reflect(a, nx, ny);
      reflect(b, -nx, -ny);
    }
  }
}

Scene KinematicField::scene(const ArmModel& arm_params) const {
  Scene out;
  out.now_s = now_s_;
  out.arm = arm_params;
  out.arm.x_mm = tool_x_;
  out.arm.y_mm = tool_y_;
  if (config_.arm_motion) {
    out.arm.joints_known = true;
    out.arm.joints_rad = config_.arm_motion->joints();
  }
  const auto& w = config_.workcell;
  out.arm.lowered = tool_z_ < 0.5 * (w.elevation_plane_z_mm + w.object_plane_z_mm);
  for (const SimSheep& s : sheep_) {
    if (!s.on_field) continue;
    const bool hidden = s.hidden_since_s >= 0.0;
    // A turn is not seen while the sheep is hidden (it happened after it was
    // hidden) nor before the lag has passed.
    const bool turn_unseen = (hidden && s.turned_at_s >= s.hidden_since_s) ||
                             now_s_ < s.turned_at_s + config_.velocity_lag_s;
    const double heading = turn_unseen ? s.old_heading : s.heading;
    out.sheep.push_back(Sheep{s.id, s.x, s.y, s.speed * std::cos(heading),
                              s.speed * std::sin(heading),
                              hidden ? SheepState::kObscured : SheepState::kVisible});
  }
  return out;
}

int KinematicField::sheep_on_field() const {
  int n = 0;
  for (const SimSheep& s : sheep_) n += s.on_field ? 1 : 0;
  return n;
}

}  // namespace ephor::planner
