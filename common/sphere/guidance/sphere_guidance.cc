#include "common/sphere/guidance/sphere_guidance.h"

#include <cmath>
#include <cstdint>

namespace ephor::sphere {

SphereGuidance::SphereGuidance(const GuidanceConfig& config)
    : config_(config), tracker_(config.tracker), controller_(config.approach) {}

std::optional<GuidanceOutput> SphereGuidance::on_estimate(const EstimateInput& e) {
  const bool finite =
      std::isfinite(e.window_end_s) &&
      (!e.ok || (std::isfinite(e.t_s) && e.position_m.allFinite() && e.velocity_m_s.allFinite()));
  const bool plausible =
      std::abs(e.window_end_s) <= kMaxTimeS &&
      (!e.ok || (std::abs(e.t_s) <= kMaxTimeS && e.position_m.norm() <= kMaxDistanceM));
  if (!finite || !plausible) {
    ++bad_;
    return std::nullopt;
  }
  if (last_window_ && e.window <= *last_window_) {
    // How far back, in uint64_t: the windows are any int64_t, and their
    // difference (>= 0 here) may not fit one.
    const uint64_t back = static_cast<uint64_t>(*last_window_) - static_cast<uint64_t>(e.window);
    if (back <= static_cast<uint64_t>(kRestartWindows)) {
      ++bad_;  // a repeat or out of order
      return std::nullopt;
    }
    // Far back: the ranger started again (its scan clock restarts at 0), or
    // the last one was bogus. Start a new track; the chaser keeps its velocity.
    tracker_.reset();
    updates_in_track_ = 0;
    ++restarts_;
  }
  last_window_ = e.window;

  GuidanceOutput out;
  out.apply_t_s = e.window_end_s + config_.approach.window_s;
  if (e.ok) {
    const Eigen::Vector3d sigma = config_.measurement_sigma_m > 0
                                      ? Eigen::Vector3d::Constant(config_.measurement_sigma_m)
                                      : paper_measurement_sigma_m(e.position_m.z());
    // The window's own velocity is not a hint: at 20 m Scan Line Extent's
    // is off by tens of cm/s now and then, and a track started on it flies
    // the chaser the wrong way. A new track starts at rest with a wide sigma.
    out.update = tracker_.update(e.t_s, e.position_m, sigma);
    switch (out.update) {
      case SphereTracker::Update::kInitialised:
      case SphereTracker::Update::kReinitialised:
        updates_in_track_ = 1;
        out.used_estimate = true;
        ++used_;
        break;
      case SphereTracker::Update::kDownweighted:
        ++downweighted_;
        [[fallthrough]];
      case SphereTracker::Update::kAccepted:
        ++updates_in_track_;
        out.used_estimate = true;
        ++used_;
        break;
      case SphereTracker::Update::kRejected:
      case SphereTracker::Update::kOutOfOrder:
        ++rejected_;
        break;
    }
  } else {
    ++none_;
  }

  out.tracking = tracker_.initialised() && updates_in_track_ >= config_.min_updates;
  if (tracker_.initialised()) {
    out.state = tracker_.predict(e.ok ? std::max(e.t_s, tracker_.time_s()) : e.window_end_s);
  }
  if (out.tracking) {
    const TrackPrediction at_apply = tracker_.predict(out.apply_t_s);
    out.command = controller_.command(at_apply.position_m, at_apply.velocity_m_s, commanded_);
  } else {
    out.command = controller_.hold(commanded_);
  }
  const Eigen::Vector3d burn = out.command.chaser_velocity_m_s - commanded_;
  if (burn.squaredNorm() > 0.0) tracker_.schedule_velocity_change(out.apply_t_s, -burn);
  commanded_ = out.command.chaser_velocity_m_s;
  return out;
}

}  // namespace ephor::sphere
