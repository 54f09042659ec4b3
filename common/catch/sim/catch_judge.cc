#include "common/catch/sim/catch_judge.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace ephor::catching {
namespace {

std::string mm(double v) { return std::to_string(static_cast<long>(std::lround(v))) + " mm"; }

}  // namespace

CatchJudge::CatchJudge(const BoardSpec& board, const BoardPlacement& placement, CupSpec cup,
                       double plane_tolerance_mm)
    : board_(board), placement_(placement), cup_(cup), plane_tolerance_mm_(plane_tolerance_mm) {
  if (!(cup_.inner_radius_mm > board_.ball_radius_mm()))
    throw std::invalid_argument("catch judge: the cup's inner radius must exceed the ball's");
  if (!(plane_tolerance_mm_ >= 0.0))
    throw std::invalid_argument("catch judge: plane_tolerance_mm must be >= 0");
}

double CatchJudge::catch_plane_z_w_mm() const {
  return placement_.bottom_centre_w_mm.z() - kCatchPlaneBelowEdgeMm;
}

CatchJudge::Crossing CatchJudge::crossing(const BoardExit& exit, double plane_z_w_mm) const {
  // Same flight as ballistic_crossing(), for any horizontal plane.
  const Pose b2w = board_to_world(board_, placement_);
  const Eigen::Vector3d p =
      b2w * Eigen::Vector3d(exit.x_b_mm, board_.height_mm, board_.ball_radius_mm());
  const Eigen::Vector3d v =
      b2w.linear() * Eigen::Vector3d(exit.velocity_b_mm_s.x(), exit.velocity_b_mm_s.y(), 0.0);
  // z(t) = p.z + v.z t - g t^2 / 2 = plane: the later root. A plane above the
  // flight's apex is never crossed: take the apex.
  const double a = -0.5 * kGravityMmS2, b = v.z(), c = p.z() - plane_z_w_mm;
  const double t = (-b - std::sqrt(std::max(0.0, b * b - 4.0 * a * c))) / (2.0 * a);
  return {p + v * t + Eigen::Vector3d(0.0, 0.0, -0.5 * kGravityMmS2 * t * t), exit.time_s + t};
}

CatchJudge::Crossing CatchJudge::catch_plane_crossing(const BoardExit& exit) const {
  return crossing(exit, catch_plane_z_w_mm());
}

CatchVerdict CatchJudge::stalled() {
  CatchVerdict v;
  v.caught = false;
  v.reason = "ball stalled on the board";
  v.miss_distance_mm = std::numeric_limits<double>::quiet_NaN();
  return v;
}

CatchVerdict CatchJudge::judge(const BoardExit& exit,
                               const Eigen::Vector3d& cup_opening_w_mm) const {
  return judge(std::optional<BoardExit>(exit),
               [&cup_opening_w_mm](double) { return cup_opening_w_mm; });
}

CatchVerdict CatchJudge::judge(const std::optional<BoardExit>& exit,
                               const CupTrajectory& cup) const {
  if (!exit) return stalled();
  // The moment the ball falls through the opening's plane, where the cup's
  // height is taken at that moment: a few fixed-point iterations from the
  // catch plane's crossing.
  Crossing x = catch_plane_crossing(*exit);
  Eigen::Vector3d opening = cup(x.time_s);
  for (int i = 0; i < 8; ++i) {
    const Crossing next = crossing(*exit, opening.z());
    const bool settled = std::abs(next.time_s - x.time_s) < 1e-6;
    x = next;
    opening = cup(x.time_s);
    if (settled) break;
  }
  CatchVerdict v;
  v.ball_w_mm = x.point_w_mm;
  v.time_s = x.time_s;
  v.height_error_mm = opening.z() - catch_plane_z_w_mm();
  v.miss_distance_mm = (x.point_w_mm.head<2>() - opening.head<2>()).norm();
  if (std::abs(v.height_error_mm) > plane_tolerance_mm_) {
    v.reason = "cup not at the catch plane: " + mm(std::abs(v.height_error_mm)) +
               (v.height_error_mm > 0.0 ? " above" : " below");
    return v;
  }
  const double allowed = cup_.inner_radius_mm - board_.ball_radius_mm();
  if (v.miss_distance_mm > allowed) {
    v.reason = "cup " + mm(v.miss_distance_mm) + " from the ball's path";
    return v;
  }
  v.caught = true;
  v.reason = "caught: cup " + mm(v.miss_distance_mm) + " from the ball's path";
  return v;
}

}  // namespace ephor::catching
