#include "common/catch/worldmodel/ball_measurement_gate.h"

#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>

namespace ephor::catching {

const char* to_string(RejectReason reason) {
  switch (reason) {
    case RejectReason::kNone:
      return "none";
    case RejectReason::kNoIntersection:
      return "no intersection";
    case RejectReason::kNotFinite:
      return "not finite";
    case RejectReason::kOutOfOrder:
      return "out of order";
    case RejectReason::kOffBoard:
      return "off board";
    case RejectReason::kJump:
      return "jump";
    case RejectReason::kAfterExit:
      return "after exit";
    case RejectReason::kNotAtStart:
      return "no ball yet and not high on the board where balls start";
  }
  return "?";
}

BallMeasurementGate::BallMeasurementGate(const BoardSpec& board, const BoardPlacement& placement,
                                         const BallGateParams& params)
    : board_(board), params_(params) {
  if (!(board.width_mm > 0.0) || !(board.height_mm > 0.0)) {
    throw std::invalid_argument("BallMeasurementGate: board size must be positive, got " +
                                std::to_string(board.width_mm) + " x " +
                                std::to_string(board.height_mm) + " mm");
  }
  if (!(placement.incline_rad > 0.0) || !(placement.incline_rad < std::numbers::pi / 2.0)) {
    throw std::invalid_argument("BallMeasurementGate: incline must be in (0, pi/2) rad, got " +
                                std::to_string(placement.incline_rad));
  }
  if (!(params.edge_margin_mm >= 0.0) || !(params.speed_margin_mm_s >= 0.0) ||
      !(params.measurement_margin_mm >= 0.0) || params.reacquire_after < 1) {
    throw std::invalid_argument(
        "BallMeasurementGate: margins must be >= 0 and reacquire_after >= 1");
  }
  acceleration_mm_s2_ = 5.0 / 7.0 * kGravityMmS2 * std::sin(placement.incline_rad);
  max_speed_mm_s_ = std::sqrt(2.0 * acceleration_mm_s2_ * board.height_mm);
}

double BallMeasurementGate::jump_limit_mm(double dt_s) const {
  return (max_speed_mm_s_ + params_.speed_margin_mm_s) * dt_s +
         0.5 * acceleration_mm_s2_ * dt_s * dt_s + params_.measurement_margin_mm;
}

int BallMeasurementGate::rejected_total() const {
  return std::accumulate(rejected_.begin(), rejected_.end(), 0);
}

void BallMeasurementGate::reset() {
  has_reference_ = false;
  consecutive_rejections_ = 0;
}

void BallMeasurementGate::note_rejection(RejectReason reason) { reject(reason, GateDecision{}); }

GateDecision BallMeasurementGate::reject(RejectReason reason, GateDecision decision) {
  decision.accepted = false;
  decision.acquired = false;
  decision.reason = reason;
  ++rejected_[static_cast<int>(reason)];
  if (++consecutive_rejections_ >= params_.reacquire_after) {
    // The reference is stale (the ball left) or was itself spurious.
    has_reference_ = false;
    consecutive_rejections_ = 0;
  }
  return decision;
}

GateDecision BallMeasurementGate::check(double t_s, const Eigen::Vector2d& p_b_mm) {
  GateDecision decision;
  if (!std::isfinite(t_s) || !p_b_mm.allFinite()) return reject(RejectReason::kNotFinite, decision);
  const double m = params_.edge_margin_mm;
  if (p_b_mm.x() < -m || p_b_mm.x() > board_.width_mm + m || p_b_mm.y() < -m ||
      p_b_mm.y() > board_.height_mm + m) {
    return reject(RejectReason::kOffBoard, decision);
  }
  if (has_reference_) {
    const double dt = t_s - reference_t_s_;
    if (!(dt > 0.0)) return reject(RejectReason::kOutOfOrder, decision);
    decision.jump_mm = (p_b_mm - reference_mm_).norm();
    decision.limit_mm = jump_limit_mm(dt);
    if (decision.jump_mm > decision.limit_mm) return reject(RejectReason::kJump, decision);
  } else {
    decision.acquired = true;
    ++acquisitions_;
  }
  decision.accepted = true;
  has_reference_ = true;
  reference_mm_ = p_b_mm;
  reference_t_s_ = t_s;
  consecutive_rejections_ = 0;
  ++accepted_;
  return decision;
}

}  // namespace ephor::catching
