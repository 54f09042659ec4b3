#pragma once
// CatchDisplayState: the catching system's page state (paper 000; issue 14):
// overlays for the camera image (the board's outline and circles through the
// pose vision found, the ball vision sees and its window of interest, the
// world model's ball with its predicted path down the board, the exit point
// with its 1-sigma span on the bottom edge, the catch point, the cup on the
// arm) and the numbers beside it (catch count against the oracle, the arm,
// the world model's status). Plain structs in (main.cc converts the LCM
// messages), JSON out (GET /api/state). Image points are px (u right, v
// down); B, W as in common/catch/board_model.h, mm; times in ms unless named.
//
// The predicted path: from the filtered position and velocity, with the
// constant acceleration down the slope that makes the world model's own
// exit time and point come out (its model: no pegs, rolling acceleration),
// sampled in time and drawn on the board plane raised by the ball's radius.
//
// Not thread-safe: DisplayServer holds one lock around every call.

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "common/catch/board_model.h"
#include "procs/catch/display/board_projector.h"

namespace ephor::catch_display {

// catch_board_pose_t.
struct BoardPoseView {
  bool valid = false;
  std::string reason;
  std::array<double, 9> r{};  // board -> camera rotation, row-major
  std::array<double, 3> t_mm{};
  std::array<double, 8> circles_px{};  // u, v: top-left, top-right, bottom-left, bottom-right
  double reprojection_rms_px = 0.0;
};

// catch_survey_t: the three touched points, in B and in W.
struct SurveyView {
  double board_mm[3][2] = {};
  double world_mm[3][3] = {};
};

// catch_ball_t.
struct BallView {
  int64_t frame_index = 0;
  bool found = false;
  double u = 0, v = 0;            // crescent-corrected centre, px
  double u_blob = 0, v_blob = 0;  // the paper's blob centroid, px
  int area_px = 0;
  std::array<int, 4> window{};  // u0, v0, u1, v1 (px, inclusive)
  double exec_ms = 0;
};

// catch_world_t.
struct WorldView {
  int64_t utime = 0;  // capture time of its frame, us
  int64_t frame_index = 0;
  int status = 0;  // catch_world_t.STATUS_*: 0 no ball, 1 tracking, 2 rejected, 3 exited
  int ball_id = 0;
  std::string reason;
  std::array<double, 2> position_b_mm{}, velocity_b_mm_s{};  // NaN when none
  bool has_prediction = false;
  double exit_x_b_mm = 0, exit_sigma_mm = 0;
  int64_t exit_utime = 0;
  double exit_sigma_s = 0;
  std::array<double, 3> catch_point_w_mm{};
  int64_t catch_utime = 0;
  double latency_ms = 0;
};

// catch_truth_t (the simulator's).
struct TruthView {
  int ball = 0;
  int phase = 0;                    // catch_truth_t.PHASE_*: 0 waiting, 1 rolling, 2 flying, 3 done
  std::array<double, 2> ball_px{};  // NaN when not in view
  double incline_deg = 0;
  int balls_done = 0, caught = 0, oracle_reachable = 0;
  int last_ball = -1;
  bool last_caught = false, last_oracle_reachable = false;
  std::string last_reason;
};

// arm_state_t: the tool tip (the cup's opening centre) in W.
struct ArmView {
  double x_mm = 0, y_mm = 0, z_mm = 0;
  bool moving = false;
  double speed_mm_s = 0;
};

struct CatchDisplayOptions {
  int path_points = 16;  // samples of the predicted path
  int rim_points = 24;   // samples of the cup's rim
  catching::CupSpec cup;
};

class CatchDisplayState {
 public:
  CatchDisplayState(catching::BoardSpec board, catching::CameraIntrinsics camera,
                    CatchDisplayOptions options = {});

  // now_us: wall clock when the message arrived (for ages in the JSON).
  void on_frame(int64_t frame_index, int width_px, int height_px, int64_t now_us);
  void on_board_pose(const BoardPoseView& pose, int64_t now_us);
  void on_survey(const SurveyView& survey, int64_t now_us);
  void on_ball(const BallView& ball, int64_t now_us);
  void on_world(const WorldView& world, int64_t now_us);
  void on_truth(const TruthView& truth, int64_t now_us);
  void on_arm(const ArmView& arm, int64_t now_us);

  nlohmann::json to_json(int64_t now_us) const;

  const BoardProjector& projector() const { return projector_; }

 private:
  nlohmann::json board_json(int64_t now_us) const;
  nlohmann::json world_json(int64_t now_us) const;
  nlohmann::json arm_json(int64_t now_us) const;

  catching::BoardSpec board_;
  CatchDisplayOptions options_;
  BoardProjector projector_;
  int64_t frame_index_ = -1;
  int width_px_ = 0, height_px_ = 0;
  int64_t frame_us_ = 0;
  std::optional<BoardPoseView> pose_;
  int64_t pose_us_ = 0;
  bool surveyed_ = false;
  std::string survey_problem_;  // why the newest survey was refused
  std::optional<catching::BoardPlacement> placement_;
  std::optional<BallView> ball_;
  int64_t ball_us_ = 0;
  std::optional<WorldView> world_;
  int64_t world_us_ = 0;
  std::optional<TruthView> truth_;
  int64_t truth_us_ = 0;
  std::optional<ArmView> arm_;
  int64_t arm_us_ = 0;
};

}  // namespace ephor::catch_display
