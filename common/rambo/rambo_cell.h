#pragma once
// The simulated RAMBO cell (paper 001, section 2) shared by the simulator and
// the processes that need the same constants: the target (a truncated box
// carrying light-sensitive diodes, each with its goal point for the laser),
// its free-floating tumbling motion drawn from a seed, the camera and laser on
// the PUMA 560's tool plate, and the arm's start joints.
//
// Frames: base = the PUMA 560's base frame (mm, z up along joint 1); target
// frame = the box's centred frame; tool = the tip frame of Puma560::forward
// (z = approach axis); camera = OpenCV's (z forward, x right, y down).
//
// Diodes (our numbers: the paper says only that the beam must be "roughly
// aligned" with the lens's axis and held "for given durations"): a diode
// fires while the beam passes within kLensRadiusMm of its lens centre and
// within kAcceptanceDeg of its optical axis; it is tagged after kRequiredS
// lit without a break.
//
// The target (vertices, faces, diodes, inertia) comes from a model file
// (common/rambo/target_model_file.h, deploy/rambo/target.pbtxt);
// RamboCell::builtin_target() is the same target in code, for unit tests.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/arm/puma560.h"
#include "common/rambo/image_triple.h"
#include "common/rambo/target_model.h"

namespace ephor::rambo {

struct Diode {
  std::string name;
  Eigen::Vector3d lens_mm = Eigen::Vector3d::Zero();  // lens centre, target frame, mm
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();    // optical axis, outward unit, target frame
  double standoff_mm = 200.0;  // goal point: the laser's tip this far out on the axis, mm
};

// The target as a model file gives it (target frame, mm), before the checks
// TargetModel makes.
struct TargetSpec {
  std::vector<Eigen::Vector3d> vertices_mm;
  std::vector<std::vector<int>> faces;
  std::vector<Diode> diodes;                                        // at most RamboCell::kMaxDiodes
  Eigen::Vector3d principal_moments_mm2 = Eigen::Vector3d::Ones();  // per unit mass
};

struct TumblingMotion {
  Eigen::Isometry3d pose0 = Eigen::Isometry3d::Identity();     // target in base at t = 0, mm
  Eigen::Vector3d velocity_mm_s = Eigen::Vector3d::Zero();     // base frame
  Eigen::Vector3d body_rates_rad_s = Eigen::Vector3d::Zero();  // target frame at t = 0
};

struct RamboCell {
  static constexpr double kAcceptanceDeg = 5.0;
  static constexpr double kLensRadiusMm = 12.0;
  static constexpr double kRequiredS = 1.0;
  static constexpr double kStandoffMm = 200.0;  // goal point: this far out on the axis, mm
  // A target carries at most this many diodes: exhaustive ordering (section
  // 10) computes 109 600 reaching trajectories for 8, and the planner orders
  // them all each time its task changes.
  static constexpr int kMaxDiodes = 8;

  TargetModel model;  // goals = one per diode, same order
  std::vector<Diode> diodes;
  Eigen::Vector3d principal_moments;  // about the target axes (box of uniform density)
  CameraIntrinsics camera;
  Eigen::Isometry3d camera_in_tool = Eigen::Isometry3d::Identity();
  arm::Joints start_joints = arm::Joints::Zero();
  double tool_length_mm = 100.0;  // flange to the laser's exit (the tool tip)

  // The cell carrying the first `diode_count` diodes of `target`. Throws
  // std::invalid_argument for a count outside 1..target.diodes.size() or a
  // bad model (TargetModel's reasons).
  static RamboCell make(const TargetSpec& target, int diode_count);
  // The same with builtin_target(): 1-4 diodes.
  static RamboCell make(int diode_count = 4);

  // deploy/rambo/target.pbtxt's first four diodes in code: a 240 x 180 x 140
  // mm box with one corner cut off, diodes on the faces turned towards the arm.
  static TargetSpec builtin_target();

  // A slow tumble: centred 900 mm out along +x of the base and 100 mm up, turning at
  // spin_deg_s about a seed-drawn axis, drifting at most drift_mm_s.
  TumblingMotion draw_motion(std::uint64_t seed, double spin_deg_s, double drift_mm_s) const;

  // The laser's tool pose (base, mm) that puts the tool tip on diode i's goal
  // point with the beam (tool z) along the axis into the lens.
  Eigen::Isometry3d goal_in_target(int i) const;
};

}  // namespace ephor::rambo
