#pragma once
// The peer for the camera's pose on the flange (issue 16's benchmark):
// OpenCV's hand-eye calibrations, cv::calibrateHandEye (Tsai, Park, Horaud,
// Andreff, Daniilidis: AX = XB) and cv::calibrateRobotWorldHandEye (Shah,
// Li: AX = ZB, the target's place found too), on views of a target: per
// view, the flange's pose in the arm's base frame (the joint readings
// through the software's arm model - with the arm's zero-reference errors
// unknown, that model is wrong, and the peer has no way to see it) and the
// target's pose in the camera frame (DotTarget, solvePnP).
//
// Units: mm, rad; frames as sensor_model.h (base, flange, camera, target).

#include <cstddef>
#include <vector>

#include <Eigen/Geometry>

namespace ephor::stripe {

enum class HandEyeMethod { kTsai, kPark, kHoraud, kAndreff, kDaniilidis, kShah, kLi };

inline constexpr HandEyeMethod kHandEyeMethods[] = {
    HandEyeMethod::kTsai,    HandEyeMethod::kPark,       HandEyeMethod::kHoraud,
    HandEyeMethod::kAndreff, HandEyeMethod::kDaniilidis, HandEyeMethod::kShah,
    HandEyeMethod::kLi};

// OpenCV's name: TSAI, PARK, HORAUD, ANDREFF, DANIILIDIS, SHAH, LI.
const char* hand_eye_method_name(HandEyeMethod method);

struct HandEyeView {
  Eigen::Isometry3d flange_in_base;    // flange -> base, by the arm model
  Eigen::Isometry3d target_in_camera;  // target -> camera, by PnP
};

// The camera's pose on the flange (camera -> flange, the paper's C_T) by
// `method` over the views (every pair of them: OpenCV forms all pairs'
// relative motions). Translations go to OpenCV in metres: in mm the
// Kronecker-product methods (ANDREFF, LI) weigh the translations a
// thousand times over the rotations and their rotation suffers. Throws
// std::invalid_argument with fewer than 3 views.
Eigen::Isometry3d solve_hand_eye(const std::vector<HandEyeView>& views, HandEyeMethod method);

// The largest set of views (greedy from each view in turn) whose flange
// orientations all differ from each other by less than max_deg. Why:
// OpenCV's TSAI takes each pair's rotation as a quaternion's vector part
// and DANIILIDIS each pair's dual quaternion, without making the arm's and
// the camera's signs agree; for pairs turned near 180 deg the two signs
// disagree and the result is wrong (seen: 3 deg and 150 deg off on
// noise-free views), so a user keeps the views within a half turn of
// each other.
std::vector<HandEyeView> views_within(const std::vector<HandEyeView>& views, double max_deg);

}  // namespace ephor::stripe
