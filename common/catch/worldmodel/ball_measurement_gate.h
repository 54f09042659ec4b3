#pragma once
// BallMeasurementGate: the paper's two filters on the ball's 3-D position
// (paper 000, section 5.4): "world modeling filters out spurious or invalid
// data points corresponding to locations beyond the boundaries of the
// inclined board" and "locations which are displaced from the previous
// reading by more than a predefined limit ... based upon the physical setup
// (e.g., incline angle of the board) and the time delay between samples".
//
// The limit here is derived rather than hand-set. A solid ball rolling
// without slipping accelerates at a = 5/7 g sin(incline) down the slope;
// released at rest, the fastest it can be anywhere on the board is after
// rolling the whole height H: v_max = sqrt(2 a H) (pegs only take energy
// away). Between two samples dt apart it moves at most
//   limit(dt) = (v_max + speed_margin) dt + a dt^2 / 2 + measurement_margin
// where speed_margin allows for a ball thrown in or an incline that is off,
// and measurement_margin for the centroid noise of both samples. dt is the
// time since the last *accepted* sample, so the window opens while samples
// are rejected. After `reacquire_after` rejections in a row the reference is
// dropped and the next on-board point starts a new ball (the old one left,
// or the reference itself was a spurious point).
//
// Positions are (x, y) in the board frame B, mm; times in s on any clock
// that increases. Not thread-safe; one owner.

#include <array>

#include <Eigen/Core>

#include "common/catch/board_model.h"

namespace ephor::catching {

// Why a measurement was not used. kNoIntersection and kNotFinite are found
// before the gate (by BoardRay) and only counted here.
enum class RejectReason {
  kNone = 0,
  kNoIntersection,  // the pixel's ray does not meet the board plane
  kNotFinite,       // NaN or infinite input, or a capture time out of range
  kOutOfOrder,      // capture time not after the last accepted sample's
  kOffBoard,        // outside [0, width] x [0, height] plus the margin
  kJump,            // farther from the last accepted point than the ball can roll
  kAfterExit,       // near the bottom edge just after the ball left (BallWorldModel)
  kNotAtStart,      // no ball yet, and not where balls are released (BallWorldModel)
};
inline constexpr int kRejectReasonCount = 7;
const char* to_string(RejectReason reason);

struct BallGateParams {
  double edge_margin_mm = 10.0;         // the board outline is widened by this
  double speed_margin_mm_s = 300.0;     // added to sqrt(2 a H)
  double measurement_margin_mm = 10.0;  // centroid noise of two samples, ~5 sigma of 1.5 mm
  int reacquire_after = 4;              // consecutive rejections that drop the reference
};

struct GateDecision {
  bool accepted = false;
  bool acquired = false;  // accepted as the first point of a (new) ball
  RejectReason reason = RejectReason::kNone;
  double jump_mm = 0.0;   // distance from the reference (0 if none)
  double limit_mm = 0.0;  // the allowed distance for this dt (0 if none)
};

class BallMeasurementGate {
 public:
  // Throws std::invalid_argument for a non-positive board size, an incline
  // outside (0, pi/2), negative margins or reacquire_after < 1.
  BallMeasurementGate(const BoardSpec& board, const BoardPlacement& placement,
                      const BallGateParams& params = {});

  // Judges the point `p_b_mm` (x, y in B) seen at `t_s`; an accepted point
  // becomes the reference for the next.
  GateDecision check(double t_s, const Eigen::Vector2d& p_b_mm);
  // Counts a rejection decided elsewhere (no ray, not finite, after exit);
  // it also counts towards re-acquisition.
  void note_rejection(RejectReason reason);
  // Drops the reference: the next on-board point is acquired.
  void reset();

  // a = 5/7 g sin(incline), mm/s^2, down the slope (+y of B).
  double rolling_acceleration_mm_s2() const { return acceleration_mm_s2_; }
  // sqrt(2 a H), mm/s.
  double max_speed_mm_s() const { return max_speed_mm_s_; }
  // The allowed displacement after `dt_s`, mm.
  double jump_limit_mm(double dt_s) const;

  bool has_reference() const { return has_reference_; }
  int accepted() const { return accepted_; }
  int acquisitions() const { return acquisitions_; }
  int rejected(RejectReason reason) const { return rejected_[static_cast<int>(reason)]; }
  int rejected_total() const;
  int consecutive_rejections() const { return consecutive_rejections_; }

 private:
  GateDecision reject(RejectReason reason, GateDecision decision);

  BoardSpec board_;
  BallGateParams params_;
  double acceleration_mm_s2_;
  double max_speed_mm_s_;
  bool has_reference_ = false;
  Eigen::Vector2d reference_mm_ = Eigen::Vector2d::Zero();
  double reference_t_s_ = 0.0;
  int consecutive_rejections_ = 0;
  int accepted_ = 0;
  int acquisitions_ = 0;
  std::array<int, kRejectReasonCount> rejected_{};
};

}  // namespace ephor::catching
