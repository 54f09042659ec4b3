#pragma once
// BallWorldModel: NASREM's world modelling for the catching system (paper
// 000, section 5.4), one call per camera frame. It turns the vision's ball
// centroid (px) into the ball's 3-D position by inverse perspective
// (BoardRay), filters out spurious points the paper's way
// (BallMeasurementGate), smooths position and velocity on the board
// (BallKalmanFilter) and predicts where the ball will leave the board and
// cross the catch plane (ExitPredictor). The process publishes one
// BallFrame per camera frame, whether or not a ball was seen.
//
// Life of a ball:
//   NO_BALL --accepted point--> TRACKING --centre past y = height--> EXITED
//   TRACKING --no accepted point for coast_limit_s--> NO_BALL (lost)
//   EXITED --exited_hold_s later, or a new ball high on the board--> ...
// A frame whose centroid was not used is REJECTED (with the reason) while a
// ball is tracked or none is; the track, if any, coasts on the filter and
// the prediction is still given. While EXITED the prediction made just
// before the ball crossed the edge is repeated (Prim aims at it), and
// points below `height - reacquire_clearance_mm` are ignored (kAfterExit):
// the falling ball still shows up in the image and its ray meets the board
// plane near the edge.
//
// Times: capture utime (us, any clock the caller keeps increasing). Frames
// and units as in common/catch/board_model.h. Not thread-safe; one
// owner (the process's task loop).

#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "common/catch/board_model.h"
#include "common/catch/worldmodel/ball_kalman_filter.h"
#include "common/catch/worldmodel/ball_measurement_gate.h"
#include "common/catch/worldmodel/board_ray.h"
#include "common/catch/worldmodel/exit_predictor.h"
#include "common/catch/worldmodel/exit_spread.h"

namespace ephor::catching {

enum class BallStatus { kNoBall, kTracking, kRejected, kExited };
const char* to_string(BallStatus status);

struct BallWorldModelParams {
  BallGateParams gate;
  // acceleration_mm_s2 is replaced by 5/7 g sin(incline) of the placement.
  BallKalmanParams filter;
  ExitPredictorParams exit;
  // Centroid noise (px, per axis); mapped to mm through the ray's Jacobian
  // at each point, so it grows with range and obliquity.
  double pixel_sigma_px = 0.5;
  double coast_limit_s = 0.25;  // no accepted point for this long: the ball is lost
  double exited_hold_s = 1.0;   // EXITED is reported this long after the exit
  double reacquire_clearance_mm = 150.0;
  // A new ball is acquired only this far down the board (y of B, mm): balls
  // are released at the top, and motion lower down with no ball tracked is
  // the arm moving in view. Infinity = anywhere.
  double acquire_max_y_mm = std::numeric_limits<double>::infinity();
  // The spread of the exit (ExitSpread: states drawn from the filter's
  // covariance and pegs from their survey error, each rolled past the pegs)
  // with every prediction while tracking; spread.samples = 0: none.
  ExitSpreadParams spread{0};
};

struct BallFrame {
  int64_t utime = 0;  // the capture time this frame describes
  BallStatus status = BallStatus::kNoBall;
  RejectReason reason = RejectReason::kNone;  // why the centroid was not used
  int ball_id = 0;                            // 0 before the first ball; +1 for every acquisition
  bool acquired = false;                      // this frame started a ball
  bool bounce = false;  // the filter inflated its noise for a bounce this frame

  // The measurement (if a centroid came and its ray met the board plane).
  bool has_measurement = false;
  Eigen::Vector3d measured_b_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d measured_w_mm = Eigen::Vector3d::Zero();

  // The filtered ball (TRACKING, REJECTED with a track, EXITED).
  bool has_state = false;
  Eigen::Vector2d position_b_mm = Eigen::Vector2d::Zero();    // ball centre, B (z = r)
  Eigen::Vector2d velocity_b_mm_s = Eigen::Vector2d::Zero();  // B
  Eigen::Vector3d position_w_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_w_mm_s = Eigen::Vector3d::Zero();
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();  // of (x, y, vx, vy) in B

  // The exit and catch prediction (see ExitPrediction) and its absolute times.
  bool has_prediction = false;
  ExitPrediction exit;
  int64_t exit_utime = 0;
  int64_t catch_utime = 0;

  // The spread of the prediction (params.spread.samples > 0, with a
  // prediction) and the absolute catch time of its cover.
  bool has_spread = false;
  ExitSpreadResult spread;
  int64_t cover_catch_utime = 0;
};

class BallWorldModel {
 public:
  // Throws std::invalid_argument on bad geometry or parameters.
  BallWorldModel(const BoardSpec& board, const BoardPlacement& placement,
                 const CameraIntrinsics& intrinsics, const Pose& board_to_camera,
                 const BallWorldModelParams& params = {});

  // One camera frame: `centroid_px` is the ball's image centroid, or nullopt
  // when the vision found none. A capture time not after the previous one is
  // REJECTED (kOutOfOrder) and changes nothing. The reference stays valid
  // until the next call.
  const BallFrame& update(int64_t capture_utime, const std::optional<Eigen::Vector2d>& centroid_px);
  void reset();
  // The board's pegs for the exit prediction (ExitPredictor::set_pegs).
  // Both the filter's predict step and the exit prediction bounce the ball
  // off them.
  void set_pegs(std::vector<Eigen::Vector2d> centres_b_mm, double peg_radius_mm) {
    filter_.set_pegs(centres_b_mm, peg_radius_mm + board_.ball_radius_mm());
    predictor_.set_pegs(std::move(centres_b_mm), peg_radius_mm);
  }

  const BallFrame& last() const { return frame_; }
  const BoardRay& ray() const { return ray_; }
  const BallMeasurementGate& gate() const { return gate_; }
  const BallKalmanFilter& filter() const { return filter_; }
  const ExitPredictor& predictor() const { return predictor_; }
  int frames() const { return frames_; }
  int out_of_order() const { return out_of_order_; }
  int exits() const { return exits_; }
  int lost() const { return lost_; }

 private:
  enum class Phase { kIdle, kTracking, kExited };
  Eigen::Matrix2d measurement_covariance(double u_px, double v_px,
                                         const Eigen::Vector3d& p_b) const;
  void drop_track();
  void fill_state();

  BoardSpec board_;
  BallWorldModelParams params_;
  BoardRay ray_;
  BallMeasurementGate gate_;
  BallKalmanFilter filter_;
  ExitPredictor predictor_;
  Phase phase_ = Phase::kIdle;
  bool has_time_ = false;
  int64_t first_utime_ = 0;
  int64_t last_utime_ = 0;
  int64_t last_accept_utime_ = 0;
  int64_t exited_utime_ = 0;
  int ball_id_ = 0;
  BallFrame frame_;
  BallFrame exit_frame_;  // the last TRACKING-phase frame with a prediction
  int frames_ = 0;
  int out_of_order_ = 0;
  int exits_ = 0;
  int lost_ = 0;
};

}  // namespace ephor::catching
