#pragma once
// Plain structs of the arm process's contract (the LCM messages arm_cmd_t,
// arm_ack_t and joint_state_t without LCM): what main.cc converts to and from.

#include <cstdint>
#include <string>

#include "common/arm/puma560.h"
#include "common/motion/trajectory.h"

namespace ephor::arm {

// arm_goal_t.PLANE_* and KIND_* (main.cc checks that the values agree).
inline constexpr int kPlaneElevation = 0;
inline constexpr int kPlaneObject = 1;
inline constexpr int kKindImage = 0;       // shepherding: a target in the image and a plane
inline constexpr int kKindPose = 1;        // a tool-down pose in the work cell frame F
inline constexpr int kKindJoints = 2;      // six joint angles
inline constexpr int kKindTrajectory = 3;  // a joint trajectory, executed as given (RAMBO)

// One command. Which fields count depends on `kind`.
struct ArmCommand {
  int64_t seq = 0;
  int64_t goal_id = 0;
  int kind = kKindImage;        // kKind*; anything else is invalid
  int plane = kPlaneElevation;  // kKindImage: kPlaneElevation or kPlaneObject
  double u_px = 0.0;            // kKindImage: target in the image, px
  double v_px = 0.0;
  double theta_rad = 0.0;  // kKindImage: orientation in the image, rad from +u towards +v;
                           // kKindPose: orientation about +z of F, rad
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();  // kKindPose: tool tip in F, mm
  Joints joints = Joints::Zero();                         // kKindJoints: rad
  Trajectory trajectory;        // kKindTrajectory: t from 0 (s), q (rad), qd (rad/s)
  double max_speed_mm_s = 0.0;  // 0 = the arm's default cap
};

// arm_ack_t.STATUS_* values.
enum class AckStatus : int { kAccepted = 0, kDone = 1, kRejected = 2, kFailed = 3 };
const char* to_string(AckStatus status);

struct ArmAck {
  int64_t seq = 0;
  int64_t goal_id = 0;
  AckStatus status = AckStatus::kRejected;
  std::string reason;
  double planned_duration_s = 0.0;
};

// Measured joints from the servo layer (joint_state_t).
struct ServoState {
  int64_t utime = 0;  // wall clock of the measurement, us
  Joints q = Joints::Zero();
  Joints qd = Joints::Zero();
  int64_t trajectory_seq = 0;
  bool trajectory_done = false;
  bool fault = false;
  std::string fault_reason;
};

}  // namespace ephor::arm
