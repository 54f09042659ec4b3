#pragma once
// The catching system's shared model (paper 000, NASREM ball catching): the
// inclined board with its four black circles, the ball, the camera, and the
// frames they are given in. Used by the simulator, vision, world model and
// planner of procs/catch, and by tools/ephor catch track.
//
// Frames (all lengths in mm):
// - Board frame B, right-handed: origin at the board's top-left corner as
//   seen from below the board (from behind its face), x to the right along
//   the top edge as seen from there, y down the slope, z out of the board
//   face (towards the camera). Seen from the camera's side x therefore runs
//   to the left. The board face is z = 0; the ball's centre rolls at
//   z = +ball radius. "Top-left" etc. below mean B's (small x, small y) ...
// - World frame W: the arm's work cell frame, z up (against gravity). The
//   PUMA's base frame is placed in W by the arm's work cell.
// - Camera frame C: OpenCV's pinhole convention, x right, y down in the
//   image, z along the optical axis.
// - Image: pixels, origin at the centre of the top-left pixel, u right, v down.

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ephor::catching {

// One black circle painted on the board, in B.
struct BoardCircle {
  double x_mm = 0.0;
  double y_mm = 0.0;
  double diameter_mm = 0.0;
};

// The board as a board file describes it (deploy/catch/board.pbtxt).
struct BoardSpec {
  double width_mm = 600.0;   // x extent of B
  double height_mm = 900.0;  // y extent of B (length down the slope)
  double ball_diameter_mm = 40.0;
  // top-left, top-right, bottom-left, bottom-right: (small x, small y),
  // (large x, small y), (small x, large y), (large x, large y) in B. The
  // default top-left circle is larger so that the four are told apart
  // under any camera pose (a rectangle of equal circles looks the same
  // turned by 180 degrees).
  std::array<BoardCircle, 4> circles{
      {{60.0, 60.0, 70.0}, {540.0, 60.0, 50.0}, {60.0, 840.0, 50.0}, {540.0, 840.0, 50.0}}};
  double ball_radius_mm() const { return ball_diameter_mm / 2.0; }
  bool on_board(double x_mm, double y_mm) const {
    return x_mm >= 0.0 && x_mm <= width_mm && y_mm >= 0.0 && y_mm <= height_mm;
  }
};

// A pinhole camera with OpenCV's distortion coefficients (k1 k2 p1 p2 [k3 ...]).
struct CameraIntrinsics {
  int width = 640;                 // px
  int height = 480;                // px
  double fx = 600.0, fy = 600.0;   // px
  double cx = 319.5, cy = 239.5;   // px
  std::vector<double> distortion;  // empty = none
};

// A rigid transform written as the paper's "pose of A with respect to B":
// p_B = R * p_A + t (mm).
using Pose = Eigen::Isometry3d;

constexpr double kGravityMmS2 = 9810.0;

// Where the board stands in the work cell W (z up). The board rises away
// from the arm along +x of W: its bottom edge is parallel to W's y axis,
// centred at bottom_centre_w_mm; B's y axis (down the slope) points towards
// the arm, (-cos i, 0, -sin i) in W; B's x axis is +y of W.
struct BoardPlacement {
  double incline_rad = 25.0 * 3.14159265358979323846 / 180.0;
  Eigen::Vector3d bottom_centre_w_mm{550.0, 500.0,
                                     250.0};  // deploy/catch/workcell.pbtxt: the PUMA at (0, 500)
};

// p_W = board_to_world(...) * p_B.
inline Pose board_to_world(const BoardSpec& board, const BoardPlacement& placement) {
  const double c = std::cos(placement.incline_rad), s = std::sin(placement.incline_rad);
  const Eigen::Vector3d x_b(0.0, 1.0, 0.0);
  const Eigen::Vector3d y_b(-c, 0.0, -s);
  const Eigen::Vector3d z_b(-s, 0.0, c);
  Pose pose = Pose::Identity();
  pose.linear().col(0) = x_b;
  pose.linear().col(1) = y_b;
  pose.linear().col(2) = z_b;
  pose.translation() =
      placement.bottom_centre_w_mm - board.height_mm * y_b - 0.5 * board.width_mm * x_b;
  return pose;
}

// The cup on the arm's tool: an open cylinder whose opening centre is the
// tool tip, opening up (tool pointing down). A ball is caught when its
// centre crosses the plane of the opening within inner_radius - ball radius
// of the cup's axis (decided by the simulator from geometry).
struct CupSpec {
  double inner_radius_mm = 50.0;
  double depth_mm = 60.0;
};

// The catch plane: the horizontal plane of W in which the cup waits, this
// far below the board's bottom edge. After leaving the edge the ball flies
// ballistically; it is caught where its centre crosses this plane.
constexpr double kCatchPlaneBelowEdgeMm = 80.0;

struct BallisticCrossing {
  Eigen::Vector3d point_w_mm;  // ball centre where it crosses the catch plane, W
  double flight_s = 0.0;       // time from leaving the edge to the crossing, s
};

// The ball leaves the bottom edge at exit_x_b_mm (B) with velocity
// (vx, vy) in B (mm/s, vy > 0 down the slope); where it crosses the catch
// plane. Pure geometry shared by the simulator (judging a catch) and the
// planner (aiming the cup).
inline BallisticCrossing ballistic_crossing(const BoardSpec& board, const BoardPlacement& placement,
                                            double exit_x_b_mm, double vx_b_mm_s,
                                            double vy_b_mm_s) {
  const Pose b2w = board_to_world(board, placement);
  const Eigen::Vector3d p =
      b2w * Eigen::Vector3d(exit_x_b_mm, board.height_mm, board.ball_radius_mm());
  const Eigen::Vector3d v = b2w.linear() * Eigen::Vector3d(vx_b_mm_s, vy_b_mm_s, 0.0);
  const double z_plane = placement.bottom_centre_w_mm.z() - kCatchPlaneBelowEdgeMm;
  // z(t) = p.z + v.z t - g t^2 / 2 = z_plane, positive root.
  const double a = -0.5 * kGravityMmS2, b = v.z(), c = p.z() - z_plane;
  const double t = (-b - std::sqrt(std::max(0.0, b * b - 4.0 * a * c))) / (2.0 * a);
  BallisticCrossing out;
  out.flight_s = t;
  out.point_w_mm = p + v * t + Eigen::Vector3d(0.0, 0.0, -0.5 * kGravityMmS2 * t * t);
  return out;
}

// Where the cup waits for a ball: where a ball leaving the bottom edge at
// its centre, straight down the slope at 80 % of the speed of a roll down
// the whole peg-free board (5/7 g sin i, rolling without slipping), crosses
// the catch plane. Balls fly ~100-150 mm past the edge before they fall
// through it, so waiting under the edge itself misses them all.
inline Eigen::Vector3d ready_point_w_mm(const BoardSpec& board, const BoardPlacement& placement) {
  const double a = 5.0 / 7.0 * kGravityMmS2 * std::sin(placement.incline_rad);
  const double v = 0.8 * std::sqrt(2.0 * a * board.height_mm);
  return ballistic_crossing(board, placement, board.width_mm / 2.0, 0.0, v).point_w_mm;
}

}  // namespace ephor::catching
