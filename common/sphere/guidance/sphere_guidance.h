#pragma once
// The sphere system's guidance (issue 15, "guidance"): the locator's
// half-second estimates through SphereTracker, and one chaser velocity
// command per estimate from ApproachController. Pure: ephor-sphere-guidance
// feeds it SPHERE_ESTIMATE messages and publishes what it returns; the
// approach simulation in procs/sphere/tests calls it directly.
//
// Timing (scan clock): the estimate of window k = [kW, (k+1)W) can only be
// made after (k+1)W, so the command it gives takes effect at the start of
// window k + 2, (k+2)W; the ranger starts each window's burn with the newest
// command due by then. The filter is told the burn at that time.

#include <optional>
#include <string>

#include <Eigen/Core>

#include "common/sphere/guidance/approach_controller.h"
#include "common/sphere/guidance/sphere_tracker.h"

namespace ephor::sphere {

struct GuidanceConfig {
  SphereTrackerConfig tracker;
  ApproachConfig approach;
  int min_updates = 3;               // estimates in the track before the chaser moves
  double measurement_sigma_m = 0.0;  // > 0: this instead of the paper's at the distance
};

// One locator output, as the guidance needs it.
struct EstimateInput {
  int64_t window = 0;
  double window_end_s = 0.0;
  bool ok = false;
  double t_s = 0.0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
};

struct GuidanceOutput {
  double apply_t_s = 0.0;
  ApproachCommand command;
  TrackPrediction state;  // at the estimate's time (or the window's end when there was none)
  bool tracking = false;
  SphereTracker::Update update = SphereTracker::Update::kRejected;
  bool used_estimate = false;
};

class SphereGuidance {
 public:
  explicit SphereGuidance(const GuidanceConfig& config = {});

  // Returns nullopt for an estimate that is not newer than the last one
  // (a repeat or out of order: up to kRestartWindows back), has non-finite
  // numbers or numbers no ranger gives (a centre beyond kMaxDistanceM, a
  // scan-clock time beyond kMaxTimeS either side of 0: the filter's
  // covariance, which grows with the distance squared and the time step
  // cubed, would overflow and the track be lost for good); counted. An
  // estimate further back means the ranger started again: the track starts
  // again from it.
  static constexpr int64_t kRestartWindows = 4;
  static constexpr double kMaxDistanceM = 1000.0;  // 50 times the approach's 20 m
  static constexpr double kMaxTimeS = 1e9;         // 30 years of scanning
  std::optional<GuidanceOutput> on_estimate(const EstimateInput& e);

  const Eigen::Vector3d& chaser_velocity() const { return commanded_; }
  int estimates_used() const { return used_; }
  int estimates_rejected() const { return rejected_; }
  int estimates_downweighted() const { return downweighted_; }
  int no_estimates() const { return none_; }
  int bad_inputs() const { return bad_; }
  int restarts() const { return restarts_; }
  const SphereTracker& tracker() const { return tracker_; }

 private:
  GuidanceConfig config_;
  SphereTracker tracker_;
  ApproachController controller_;
  Eigen::Vector3d commanded_ = Eigen::Vector3d::Zero();  // the chaser velocity last commanded
  std::optional<int64_t> last_window_;
  int updates_in_track_ = 0;
  int used_ = 0, rejected_ = 0, downweighted_ = 0, none_ = 0, bad_ = 0, restarts_ = 0;
};

}  // namespace ephor::sphere
