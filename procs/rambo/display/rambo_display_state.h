#pragma once
// RamboDisplayState: the RAMBO page's state (paper 001; issue 17 item 6). For
// the camera image: the corners and image edges the features process found,
// the image triangles the pose matched to model triangles and the model's
// outline projected with the estimated pose; for the 3-D view: the target's
// estimated and true poses, the camera, the laser's tool tip and beam; beside
// them the planned order of the diodes, which are tagged and which is lit.
// Plain structs in (main.cc converts the LCM messages), JSON out (GET
// /api/state, GET /api/model). Frames: base = the PUMA 560's base (mm);
// poses map target (or camera, OpenCV's) points to base: x_base = R x + t.
// Pixels: origin at the top-left pixel's centre, x right, y down.
//
// Not thread-safe: DisplayServer holds one lock around every call.

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "common/arm/puma560.h"
#include "common/rambo/rambo_cell.h"

namespace ephor::rambo_display {

// rambo_features_t.
struct FeaturesView {
  int64_t utime = 0;
  int64_t frame_index = -1;
  std::string source;
  std::vector<std::array<double, 2>> corners_px;
  std::vector<std::array<int, 2>> edges;  // indices into corners_px
  int triples = 0;
};

// rambo_pose_t.
struct PoseView {
  int64_t utime = 0;  // capture time of its frame, us
  int64_t frame_index = -1;
  bool found = false;
  std::string reason;
  Eigen::Isometry3d target_in_base = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d camera_in_base = Eigen::Isometry3d::Identity();  // at the capture time
  double pose_ms = 0;
  int correspondences = 0;
  bool pruned = false;
  std::string features_source;
  std::vector<std::array<double, 6>> matched_triangles_px;  // reference, a, b: x, y each
};

// rambo_truth_t (the simulator's).
struct TruthView {
  int64_t utime = 0;
  int64_t frame_index = -1;
  Eigen::Isometry3d target_in_base = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d camera_in_base = Eigen::Isometry3d::Identity();
  // The RM-501 carrying the target (--carrier rm501), its links as a chain
  // of points in base (mm): waist foot, shoulder, elbow, wrist, flange,
  // target origin. Empty for the free-floating target.
  std::vector<Eigen::Vector3d> carrier_mm;
};

// rambo_plan_t.
struct PlanView {
  std::vector<int> order;  // diode indices, first to be tagged first
  int current_task = -1;
  std::string status;
  int64_t greedy_trajectories = 0, exhaustive_trajectories = 0, dp_trajectories = 0;
  double order_total_s = 0;
  int64_t goals_sent = 0;
};

// rambo_indicator_t.
struct IndicatorView {
  int64_t utime = 0;
  int lit_diode = -1;
  double lit_s = 0, required_s = 0, acceptance_deg = 0;
  std::vector<bool> tagged;
  std::vector<double> tagged_utime;  // us, 0 = not yet
  std::vector<double> beam_angle_deg, beam_offset_mm;
};

class RamboDisplayState {
 public:
  explicit RamboDisplayState(rambo::RamboCell cell);

  void on_features(FeaturesView f) { features_ = std::move(f); }
  void on_pose(PoseView p);
  void on_truth(const TruthView& t);
  void on_plan(PlanView p) { plan_ = std::move(p); }
  void on_indicator(IndicatorView i) { indicator_ = std::move(i); }
  // ARM_STATE's joints (rad): the laser's tool pose by the PUMA's kinematics.
  void on_arm_joints(const arm::Joints& q);

  // GET /api/state's system part (see the top of this file).
  nlohmann::json state() const;
  // GET /api/model: the target's vertices and faces (target frame, mm), its
  // diodes (lens, axis, goal point) and the camera's intrinsics.
  nlohmann::json model() const;

  // The model's edges that face the camera, projected with `target_in_base`
  // seen from `camera_in_base`: x0, y0, x1, y1 px (exposed for tests).
  std::vector<std::array<double, 4>> outline_px(const Eigen::Isometry3d& target_in_base,
                                                const Eigen::Isometry3d& camera_in_base) const;

 private:
  std::string diode_name(int i) const;

  rambo::RamboCell cell_;
  arm::Puma560 arm_;
  std::optional<FeaturesView> features_;
  std::optional<PoseView> pose_;   // newest
  std::optional<PoseView> found_;  // newest found
  std::optional<TruthView> truth_;
  std::map<int64_t, Eigen::Isometry3d> truth_by_utime_;  // recent, for the pose's error
  std::optional<PlanView> plan_;
  std::optional<IndicatorView> indicator_;
  std::optional<Eigen::Isometry3d> tool_;
  int64_t poses_ = 0, poses_found_ = 0;
  std::optional<std::pair<double, double>> error_;  // newest found pose against the truth: mm, deg
};

}  // namespace ephor::rambo_display
