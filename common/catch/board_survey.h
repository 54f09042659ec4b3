#pragma once
// The board's place in the work cell from the arm touching three of its
// points (paper 000, section 3: "the board's pose in the arm's frame"). Each
// point is known in the board frame B (on the face, z = 0) and measured by
// the tool tip in W. The rigid transform B -> W is fitted by least squares
// (Umeyama, no scale) and expressed as a BoardPlacement: the incline and the
// bottom edge's centre. BoardPlacement assumes the bottom edge parallel to
// W's y axis (board_model.h); a fit that leaves that assumption by more than
// 2 degrees is refused, as are collinear or inconsistent points.

#include <array>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "common/catch/board_model.h"

namespace ephor::catching {

// nullopt (and `why`) when the points are not finite, nearly collinear, or do
// not fit a rigid board (residual above 5 mm), or the edge is not along W's y.
std::optional<BoardPlacement> placement_from_survey(const BoardSpec& board,
                                                    const std::array<Eigen::Vector2d, 3>& board_mm,
                                                    const std::array<Eigen::Vector3d, 3>& world_mm,
                                                    std::string& why);

// The same from catch_survey_t's arrays (board_mm[3][2], world_mm[3][3]).
std::optional<BoardPlacement> placement_from_survey(const BoardSpec& board,
                                                    const double (&board_mm)[3][2],
                                                    const double (&world_mm)[3][3],
                                                    std::string& why);

}  // namespace ephor::catching
