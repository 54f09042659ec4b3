#include "common/sphere/world/ranger_world.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ephor::sphere {
namespace {

// Mixes the run's seed with a window index (splitmix64), so each window's
// noise is independent and reproducible.
uint64_t mix(uint64_t seed, uint64_t k) {
  uint64_t z = seed + 0x9e3779b97f4a7c15ULL * (k + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

RangerWorld::RangerWorld(const RangerWorldConfig& config)
    : config_(config),
      motion_(config.motion),
      judge_(config.capture),
      rng_(mix(config.seed, 0xa99u)),
      flown_command_(config.motion.chaser_velocity_m_s) {
  const CaptureCriteria& c = config.capture;
  if (!(c.capture_distance_m > kSphereRadiusM && c.max_speed_m_s > 0 && c.max_offset_m > 0)) {
    throw std::invalid_argument(
        "capture distance must exceed the sphere's radius and the limits be positive");
  }
  if (!(config.motion.start_position_m.z() > c.capture_distance_m)) {
    throw std::invalid_argument("the sphere must start beyond the capture distance (" +
                                std::to_string(c.capture_distance_m) + " m along the boresight)");
  }
  if (!(config.max_s >= 0.0) || config.approaches < 0) {
    throw std::invalid_argument("max_s and approaches must be >= 0");
  }
  if (!(config.extent_margin >= 1.0 && config.max_half_extent_deg > 0 &&
        config.max_half_extent_deg < 80)) {
    throw std::invalid_argument("extent margin must be >= 1 and the largest frame under 80 deg");
  }
  RasterScanner check(config.scanner);  // validates the rates
  (void)check;
}

bool RangerWorld::command(double apply_t_s, const Eigen::Vector3d& chaser_velocity_m_s) {
  if (!std::isfinite(apply_t_s) || !chaser_velocity_m_s.allFinite()) return false;
  commands_.push_back({apply_t_s, chaser_velocity_m_s});
  // Keep the queue short: only commands that are not yet due matter beyond the newest due one.
  while (commands_.size() > 16) commands_.pop_front();
  return true;
}

void RangerWorld::start_window(int64_t k) {
  const double w = config_.motion.window_s;
  const double t0 = static_cast<double>(k) * w;
  // The newest command due by this window's start; later ones wait.
  for (auto it = commands_.rbegin(); it != commands_.rend(); ++it) {
    if (it->apply_t_s <= t0 + 1e-9) {
      flown_command_ = it->chaser_velocity_m_s;
      commands_.erase(commands_.begin(), it.base());
      break;
    }
  }
  if (awaiting_reset_) {
    // A fresh sphere at the start distance, drifting at the same speeds in
    // random directions across the boresight (always toward the sensor in z).
    const Eigen::Vector3d& d = config_.motion.target_velocity_m_s;
    std::uniform_int_distribution<int> coin(0, 1);
    const double sx = coin(rng_) ? 1.0 : -1.0, sy = coin(rng_) ? 1.0 : -1.0;
    motion_.reset_target(
        t0, config_.motion.start_position_m,
        Eigen::Vector3d(sx * d.x(), sy * d.y(), d.z()) + motion_.chaser_velocity());
    awaiting_reset_ = false;
    ++approach_;
    approach_start_s_ = t0;
  }
  const SphereTrajectory trajectory = motion_.begin_window(t0, flown_command_);
  judged_until_s_ = t0;

  RangeSimulatorConfig sim;
  sim.scanner = config_.scanner;
  sim.scanner.half_extent_deg = std::min(
      config_.max_half_extent_deg,
      RasterScanner::required_half_extent_deg(trajectory, t0, t0 + w, config_.extent_margin, true));
  half_extent_deg_ = sim.scanner.half_extent_deg;
  sim.sphere = trajectory;
  sim.noise = config_.noise;
  sim.background = config_.background;
  sim.seed = mix(config_.seed, static_cast<uint64_t>(k));
  RangeSimulator simulator(sim);
  std::vector<ScanLine> lines = simulator.scan(t0, w, next_line_id_);
  for (size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].pulses.empty()) continue;
    RangerLine r;
    r.window = k;
    r.last_in_window = i + 1 == lines.size();
    r.half_extent_deg = half_extent_deg_;
    r.ready_t_s = lines[i].pulses.back().t_s;
    r.line = std::move(lines[i]);
    next_line_id_ = r.line.id + 1;
    pending_.push_back(std::move(r));
  }
}

void RangerWorld::judge_until(double t_s) {
  if (awaiting_reset_ || finished() || t_s <= judged_until_s_) return;
  const SphereTrajectory trajectory = motion_.trajectory();
  std::optional<CaptureVerdict> v = judge_.judge(trajectory, judged_until_s_, t_s);
  if (!v && config_.max_s > 0 && t_s >= approach_start_s_ + config_.max_s) {
    v = judge_.give_up(trajectory, approach_start_s_ + config_.max_s);
  }
  judged_until_s_ = t_s;
  if (!v) return;
  verdicts_.push_back(*v);
  if (!finished()) awaiting_reset_ = true;
}

std::vector<RangerLine> RangerWorld::advance_to(double t_s) {
  const double w = config_.motion.window_s;
  while (!finished() && static_cast<double>(next_window_) * w <= t_s + 1e-12) {
    if (next_window_ > 0) judge_until(static_cast<double>(next_window_) * w);
    if (finished()) break;
    start_window(next_window_);
    ++next_window_;
  }
  judge_until(t_s);
  std::vector<RangerLine> ready;
  while (!pending_.empty() && pending_.front().ready_t_s <= t_s) {
    ready.push_back(std::move(pending_.front()));
    pending_.pop_front();
  }
  return ready;
}

RangerTruth RangerWorld::truth_at(double t_s) const {
  RangerTruth t;
  t.t_s = t_s;
  t.approach = approach_;
  t.position_m = motion_.position_at(t_s);
  t.velocity_m_s = motion_.relative_velocity();
  t.chaser_velocity_m_s = motion_.chaser_velocity();
  t.target_velocity_m_s = motion_.target_velocity();
  t.half_extent_deg = half_extent_deg_;
  return t;
}

bool RangerWorld::finished() const {
  return config_.approaches > 0 && static_cast<int>(verdicts_.size()) >= config_.approaches;
}

}  // namespace ephor::sphere
