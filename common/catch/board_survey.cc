#include "common/catch/board_survey.h"

#include <cmath>

#include <fmt/format.h>
#include <Eigen/Geometry>

namespace ephor::catching {

std::optional<BoardPlacement> placement_from_survey(const BoardSpec& board,
                                                    const std::array<Eigen::Vector2d, 3>& board_mm,
                                                    const std::array<Eigen::Vector3d, 3>& world_mm,
                                                    std::string& why) {
  Eigen::Matrix3d src, dst;
  for (int i = 0; i < 3; ++i) {
    if (!board_mm[i].allFinite() || !world_mm[i].allFinite()) {
      why = fmt::format("touched point {} is not finite", i + 1);
      return std::nullopt;
    }
    src.col(i) = Eigen::Vector3d(board_mm[i].x(), board_mm[i].y(), 0.0);
    dst.col(i) = world_mm[i];
  }
  const double area = (src.col(1) - src.col(0)).cross(src.col(2) - src.col(0)).norm() / 2.0;
  if (area < 1000.0) {
    why = fmt::format("the touched points are nearly collinear (triangle of {:.0f} mm^2)", area);
    return std::nullopt;
  }
  const Eigen::Matrix4d t = Eigen::umeyama(src, dst, false);
  Pose b2w(t);
  double residual = 0.0;
  for (int i = 0; i < 3; ++i) residual = std::max(residual, (b2w * src.col(i) - dst.col(i)).norm());
  if (residual > 5.0) {
    why = fmt::format("the touched points do not fit the board: {:.1f} mm off", residual);
    return std::nullopt;
  }
  const Eigen::Vector3d x_b = b2w.linear().col(0), y_b = b2w.linear().col(1);
  if (x_b.y() < std::cos(2.0 * M_PI / 180.0)) {
    why = fmt::format(
        "the board's bottom edge is {:.1f} deg off W's y axis (board_model.h wants it along y)",
        std::acos(std::clamp(x_b.y(), -1.0, 1.0)) * 180.0 / M_PI);
    return std::nullopt;
  }
  BoardPlacement p;
  p.incline_rad = std::asin(std::clamp(-y_b.z(), -1.0, 1.0));
  p.bottom_centre_w_mm = b2w * Eigen::Vector3d(board.width_mm / 2.0, board.height_mm, 0.0);
  return p;
}

std::optional<BoardPlacement> placement_from_survey(const BoardSpec& board,
                                                    const double (&board_mm)[3][2],
                                                    const double (&world_mm)[3][3],
                                                    std::string& why) {
  std::array<Eigen::Vector2d, 3> b;
  std::array<Eigen::Vector3d, 3> w;
  for (int i = 0; i < 3; ++i) {
    b[i] = Eigen::Vector2d(board_mm[i][0], board_mm[i][1]);
    w[i] = Eigen::Vector3d(world_mm[i][0], world_mm[i][1], world_mm[i][2]);
  }
  return placement_from_survey(board, b, w, why);
}

}  // namespace ephor::catching
