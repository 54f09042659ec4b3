#include "common/catch/worldmodel/ball_world_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ephor::catching {

const char* to_string(BallStatus status) {
  switch (status) {
    case BallStatus::kNoBall:
      return "NO_BALL";
    case BallStatus::kTracking:
      return "TRACKING";
    case BallStatus::kRejected:
      return "REJECTED";
    case BallStatus::kExited:
      return "EXITED";
  }
  return "?";
}

namespace {

BallKalmanParams with_acceleration(BallKalmanParams p, const BoardPlacement& placement) {
  p.acceleration_mm_s2 = 5.0 / 7.0 * kGravityMmS2 * std::sin(placement.incline_rad);
  return p;
}

// Seconds as us, saturated to +-1e6 s (a prediction further ahead is no
// prediction; llround of a value beyond int64 is undefined).
int64_t to_utime(double s) {
  if (!std::isfinite(s)) return 0;
  return static_cast<int64_t>(std::llround(std::clamp(s, -1e6, 1e6) * 1e6));
}

// Capture times beyond this (us, year 148 000) or negative are refused, so
// that every difference and sum of times below stays within int64 (found by
// the fuzz target catch_world_model).
constexpr int64_t kMaxCaptureUtime = int64_t{1} << 62;

}  // namespace

BallWorldModel::BallWorldModel(const BoardSpec& board, const BoardPlacement& placement,
                               const CameraIntrinsics& intrinsics, const Pose& board_to_camera,
                               const BallWorldModelParams& params)
    : board_(board),
      params_(params),
      ray_(board, placement, intrinsics, board_to_camera),
      gate_(board, placement, params.gate),
      filter_(with_acceleration(params.filter, placement)),
      predictor_(board, placement, filter_.acceleration_mm_s2(), params.exit) {
  if (!(params.pixel_sigma_px > 0.0) || !(params.coast_limit_s > 0.0) ||
      !(params.exited_hold_s >= 0.0) || !(params.reacquire_clearance_mm >= 0.0)) {
    throw std::invalid_argument(
        "BallWorldModel: pixel_sigma_px and coast_limit_s must be > 0, exited_hold_s and "
        "reacquire_clearance_mm >= 0");
  }
}

void BallWorldModel::reset() {
  drop_track();
  has_time_ = false;
  frame_ = BallFrame{};
  exit_frame_ = BallFrame{};
}

void BallWorldModel::drop_track() {
  phase_ = Phase::kIdle;
  filter_.reset();
  gate_.reset();
}

Eigen::Matrix2d BallWorldModel::measurement_covariance(double u_px, double v_px,
                                                       const Eigen::Vector3d& p_b) const {
  // The ray's Jacobian d(x, y)_B / d(u, v) by forward differences of one
  // pixel (the mapping is smooth on that scale).
  Eigen::Matrix2d j;
  const BoardRayHit du = ray_.intersect(u_px + 1.0, v_px);
  const BoardRayHit dv = ray_.intersect(u_px, v_px + 1.0);
  if (!du.ok() || !dv.ok()) return Eigen::Matrix2d::Identity() * 100.0;  // grazing: 10 mm
  j.col(0) = (du.point_b_mm - p_b).head<2>();
  j.col(1) = (dv.point_b_mm - p_b).head<2>();
  const double s2 = params_.pixel_sigma_px * params_.pixel_sigma_px;
  // A floor of 0.1 mm keeps R positive for a degenerate Jacobian.
  return s2 * j * j.transpose() + Eigen::Matrix2d::Identity() * 0.01;
}

void BallWorldModel::fill_state() {
  const Eigen::Isometry3d& b2w = ray_.board_to_world();
  frame_.has_state = true;
  frame_.position_b_mm = filter_.position();
  frame_.velocity_b_mm_s = filter_.velocity();
  frame_.position_w_mm = b2w * Eigen::Vector3d(frame_.position_b_mm.x(), frame_.position_b_mm.y(),
                                               board_.ball_radius_mm());
  frame_.velocity_w_mm_s =
      b2w.linear() * Eigen::Vector3d(frame_.velocity_b_mm_s.x(), frame_.velocity_b_mm_s.y(), 0.0);
  frame_.covariance = filter_.covariance();
}

const BallFrame& BallWorldModel::update(int64_t capture_utime,
                                        const std::optional<Eigen::Vector2d>& centroid_px) {
  ++frames_;
  if (capture_utime < 0 || capture_utime > kMaxCaptureUtime) {
    frame_.status = BallStatus::kRejected;
    frame_.reason = RejectReason::kNotFinite;
    frame_.acquired = false;
    frame_.bounce = false;
    return frame_;
  }
  if (has_time_ && capture_utime <= last_utime_) {
    ++out_of_order_;
    frame_.status = BallStatus::kRejected;
    frame_.reason = RejectReason::kOutOfOrder;
    frame_.acquired = false;
    frame_.bounce = false;
    return frame_;
  }
  if (!has_time_) {
    has_time_ = true;
    first_utime_ = capture_utime;
    last_utime_ = capture_utime;
  }
  const double dt_s = 1e-6 * static_cast<double>(capture_utime - last_utime_);
  last_utime_ = capture_utime;
  const double t_s = 1e-6 * static_cast<double>(capture_utime - first_utime_);

  frame_ = BallFrame{};
  frame_.utime = capture_utime;
  frame_.ball_id = ball_id_;

  if (phase_ == Phase::kExited &&
      1e-6 * static_cast<double>(capture_utime - exited_utime_) > params_.exited_hold_s) {
    drop_track();
  }
  // A gap longer than the coast limit (a stalled camera, a paused log): the
  // ball is lost, not predicted across (the filter would step through the
  // pegs for every 2 ms of it; a ball crosses the board in about a second).
  if (phase_ == Phase::kTracking && dt_s > params_.coast_limit_s) {
    ++lost_;
    drop_track();
  }
  if (phase_ == Phase::kTracking) filter_.predict(dt_s);

  // The measurement.
  bool rejected = false;
  if (centroid_px) {
    const double u = centroid_px->x(), v = centroid_px->y();
    const BoardRayHit hit = ray_.intersect(u, v);
    if (!hit.ok()) {
      frame_.reason = hit.status == RayStatus::kNotFinite ? RejectReason::kNotFinite
                                                          : RejectReason::kNoIntersection;
      gate_.note_rejection(frame_.reason);
      rejected = true;
    } else {
      frame_.has_measurement = true;
      frame_.measured_b_mm = hit.point_b_mm;
      frame_.measured_w_mm = hit.point_w_mm;
      const Eigen::Vector2d z = hit.point_b_mm.head<2>();
      if (phase_ == Phase::kExited && z.y() > board_.height_mm - params_.reacquire_clearance_mm) {
        frame_.reason = RejectReason::kAfterExit;
        gate_.note_rejection(frame_.reason);
        rejected = true;
      } else {
        if (phase_ == Phase::kExited) drop_track();  // a new ball, high on the board
        const GateDecision decision = gate_.check(t_s, z);
        const bool new_ball = decision.acquired || phase_ != Phase::kTracking;
        if (decision.accepted && new_ball && z.y() > params_.acquire_max_y_mm) {
          frame_.reason = RejectReason::kNotAtStart;
          gate_.note_rejection(frame_.reason);
          gate_.reset();
          rejected = true;
        } else if (!decision.accepted) {
          frame_.reason = decision.reason;
          rejected = true;
        } else {
          const Eigen::Matrix2d r = measurement_covariance(u, v, hit.point_b_mm);
          if (decision.acquired || phase_ != Phase::kTracking) {
            filter_.initialise(z, r);
            phase_ = Phase::kTracking;
            frame_.ball_id = ++ball_id_;
            frame_.acquired = true;
          } else {
            frame_.bounce = filter_.update(z, r).bounce;
          }
          last_accept_utime_ = capture_utime;
        }
      }
    }
  }

  // The track.
  if (phase_ == Phase::kTracking) {
    if (filter_.position().y() >= board_.height_mm) {
      phase_ = Phase::kExited;
      exited_utime_ = capture_utime;
      ++exits_;
      if (!exit_frame_.has_prediction || exit_frame_.ball_id != ball_id_) {
        // Past the edge on the first sight: predict from here.
        fill_state();
        exit_frame_ = frame_;
        exit_frame_.exit = predictor_.predict(filter_.state(), filter_.covariance());
        exit_frame_.has_prediction = exit_frame_.exit.ok();
        exit_frame_.exit_utime = capture_utime;
        exit_frame_.catch_utime = capture_utime + to_utime(exit_frame_.exit.flight_s);
      }
    } else if (1e-6 * static_cast<double>(capture_utime - last_accept_utime_) >
               params_.coast_limit_s) {
      ++lost_;
      drop_track();
    } else {
      fill_state();
      frame_.exit = predictor_.predict(filter_.state(), filter_.covariance());
      frame_.has_prediction = frame_.exit.ok();
      if (frame_.has_prediction) {
        frame_.exit_utime = capture_utime + to_utime(frame_.exit.time_to_exit_s);
        frame_.catch_utime = capture_utime + to_utime(frame_.exit.time_to_catch_s);
        if (params_.spread.samples > 0) {
          frame_.spread =
              ExitSpread(predictor_, params_.spread).sample(filter_.state(), filter_.covariance());
          frame_.has_spread = frame_.spread.ok;
          frame_.cover_catch_utime = capture_utime + to_utime(frame_.spread.cover_time_to_catch_s);
        }
        exit_frame_ = frame_;
      }
    }
  }

  switch (phase_) {
    case Phase::kExited:
      frame_.status = BallStatus::kExited;
      frame_.has_state = false;
      frame_.has_prediction = exit_frame_.has_prediction;
      frame_.exit = exit_frame_.exit;
      frame_.exit_utime = exit_frame_.exit_utime;
      frame_.catch_utime = exit_frame_.catch_utime;
      frame_.has_spread = exit_frame_.has_spread;
      frame_.spread = exit_frame_.spread;
      frame_.cover_catch_utime = exit_frame_.cover_catch_utime;
      break;
    case Phase::kTracking:
      frame_.status = rejected ? BallStatus::kRejected : BallStatus::kTracking;
      break;
    case Phase::kIdle:
      frame_.status = rejected ? BallStatus::kRejected : BallStatus::kNoBall;
      break;
  }
  return frame_;
}

}  // namespace ephor::catching
