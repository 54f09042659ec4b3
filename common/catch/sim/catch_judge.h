#pragma once
// CatchJudge: decides whether the cup caught the ball, from geometry alone.
//
// After the ball's centre crosses the board's bottom edge (BoardExit) it
// flies ballistically in W under full g (as ballistic_crossing() in
// common/catch/board_model.h). The cup is an open cylinder, opening up,
// its axis vertical through the opening's centre (the tool tip).
//
// The rule: the ball is caught when
//   1. the cup's opening is within plane_tolerance_mm (20 mm) of the catch
//      plane (kCatchPlaneBelowEdgeMm below the bottom edge) - a cup held
//      elsewhere is not waiting where the system says it catches - and
//   2. the ball's centre, falling through the horizontal plane of the
//      opening, passes within inner_radius - ball_radius of the cup's axis
//      (the ball drops in without touching the rim).
// Where the cup is: its opening's centre at the moment the ball falls
// through the opening's plane. With a trajectory (a function of time) that
// moment is found by fixed-point iteration (the cup's height may change).
// A ball that stalled on the board is never caught.
//
// The verdict's reason is a sentence for logs and test failures: "caught:
// cup 7 mm from the ball's path", "cup 43 mm from the ball's path", "cup not
// at the catch plane: 30 mm above", "ball stalled on the board".

#include <functional>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "common/catch/board_model.h"
#include "common/catch/sim/board_world.h"

namespace ephor::catching {

struct CatchVerdict {
  bool caught = false;
  std::string reason;
  // Horizontal distance from the cup's axis to the ball's centre where it
  // falls through the opening's plane, mm (NaN if the ball stalled).
  double miss_distance_mm = 0.0;
  // Cup opening height minus the catch plane's, mm (+: above).
  double height_error_mm = 0.0;
  // Ball centre where it falls through the opening's plane (W, mm) and when
  // (world clock, s).
  Eigen::Vector3d ball_w_mm = Eigen::Vector3d::Zero();
  double time_s = 0.0;
};

class CatchJudge {
 public:
  // Cup opening centre (W, mm) as a function of the world clock (s).
  using CupTrajectory = std::function<Eigen::Vector3d(double time_s)>;

  CatchJudge(const BoardSpec& board, const BoardPlacement& placement, CupSpec cup = {},
             double plane_tolerance_mm = 20.0);

  // The ball's centre on its flight after `exit` where it falls through the
  // horizontal plane z_W = plane_z_w_mm (below the exit point), W, and when.
  struct Crossing {
    Eigen::Vector3d point_w_mm;
    double time_s;  // world clock
  };
  Crossing crossing(const BoardExit& exit, double plane_z_w_mm) const;
  // Where the ball crosses the catch plane (what the planner aims for).
  Crossing catch_plane_crossing(const BoardExit& exit) const;

  // With the cup's opening fixed at `cup_opening_w_mm` while the ball falls.
  CatchVerdict judge(const BoardExit& exit, const Eigen::Vector3d& cup_opening_w_mm) const;
  // With the cup moving; `exit` empty means the ball stalled (or never left).
  CatchVerdict judge(const std::optional<BoardExit>& exit, const CupTrajectory& cup) const;
  static CatchVerdict stalled();

  double catch_plane_z_w_mm() const;

 private:
  BoardSpec board_;
  BoardPlacement placement_;
  CupSpec cup_;
  double plane_tolerance_mm_;
};

}  // namespace ephor::catching
