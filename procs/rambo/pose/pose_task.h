#pragma once
// ephor-rambo-pose's handlers and pose task, out of main.cc so that the fuzz
// target pose_task_fuzz.cc runs what the process runs: RAMBO_PREDICTION as
// the pruning prior's motion, ARM_STATE as the joints' history, the
// features messages queued until the arm has reported past their capture
// time (PoseFrameQueue), and one frame's RAMBO_POSE (FramePoser: the triples
// checked, the camera's pose from the joints, the estimate, the prior). Not
// thread-safe: main.cc holds its mutex around the queue; the poser is the
// pose task's own.

#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "common/arm/puma560.h"
#include "common/rambo/image_triple.h"
#include "common/rambo/rambo_cell.h"
#include "common/rambo/tagging_planner.h"
#include "common/rambo/triangle_pose_estimator.h"
#include "ephor/arm_state_t.hpp"
#include "ephor/rambo_features_t.hpp"
#include "ephor/rambo_pose_t.hpp"
#include "ephor/rambo_prediction_t.hpp"

namespace ephor::rambo {

// The predictor's motion (on the clock where ref_utime is its t_ref_s, s),
// orientation normalised; nullopt for a message not fitted or not finite
// (the planner names bad predictions; the pose process only ignores them).
std::optional<FittedMotion> prior_motion_of(const rambo_prediction_t& m);

// The arm's joints (rad), nullopt when one is not finite (a bad message).
std::optional<arm::Joints> joints_of(const arm_state_t& m);

// A frame ready for the pose task, with what its pose depends on as it was
// when the frame became ready.
struct ReadyFrame {
  rambo_features_t features;
  std::optional<arm::Joints> q;        // at the capture time (rad); none: camera pose unknown
  std::optional<FittedMotion> motion;  // the predictor's newest fit then
};

// Frames between the handlers and the pose task: ready ones, oldest first,
// and the newest one still waiting for an ARM_STATE at or after its capture
// time. The camera's pose is interpolated between the states around the
// capture, so a frame is taken up only once the arm has reported past it;
// what the estimate sees then does not depend on how fast messages arrived,
// and a recorded run replays to the same poses (rambo_replay_test).
class PoseFrameQueue {
 public:
  // Frames ready beyond max_behind are dropped, oldest first.
  explicit PoseFrameQueue(int max_behind) : max_behind_(max_behind) {}

  // The predictor's newest fit.
  void on_motion(const FittedMotion& motion) { motion_ = motion; }
  // An ARM_STATE's finite joints at utime (us); states not newer than the
  // last are ignored. True when the waiting frame became ready (trigger
  // the pose task).
  bool on_arm_state(int64_t utime, const arm::Joints& q);
  // A features message. True when a frame is ready (trigger the pose task).
  bool on_features(const rambo_features_t& m);
  // The oldest ready frame, if any.
  std::optional<ReadyFrame> take();
  bool has_ready() const { return !ready_.empty(); }
  int64_t dropped() const { return dropped_; }

  // The joints at utime (us), linear between ARM_STATE samples; none before
  // the first state or more than 50 ms after the last.
  std::optional<arm::Joints> joints_at(int64_t utime) const;

  // ARM_STATE history kept: 10 s at 100 Hz.
  static constexpr std::size_t kMaxStates = 1000;

 private:
  void make_ready(rambo_features_t f);

  int max_behind_;
  std::deque<std::pair<int64_t, arm::Joints>> joints_;  // utime (us) -> q (rad)
  std::deque<ReadyFrame> ready_;
  std::optional<rambo_features_t> waiting_;
  std::optional<FittedMotion> motion_;
  int64_t dropped_ = 0;  // frames not estimated: more than max_behind behind
};

// The triples of a features message as the estimator takes them; false when
// the message is malformed (num_triples not the array's size, or a
// non-finite pixel).
bool triples_of(const rambo_features_t& f, std::vector<ImageTriple>* triples);

// One frame's pose as the pose task makes it, with the last pose found (the
// prior when the predictor's motion is not fresh).
class FramePoser {
 public:
  // prior_max_age_s: prune with the last pose when it is at most this old,
  // with the predictor's motion when its reference is at most 5x this
  // before the frame (0 = never prune).
  FramePoser(const RamboCell& cell, const TrianglePoseEstimator& estimator, double prior_max_age_s);

  // The RAMBO_POSE of a frame (its utime that of the frame; pose_ms the
  // estimate's thread CPU time). *malformed is set when the features message
  // is refused (triples_of()). before_estimate, when set, is called with
  // the triples and the camera in base (mm) just before the estimate (the
  // peer's hand-off).
  rambo_pose_t pose(const ReadyFrame& frame, bool* malformed,
                    const std::function<void(const std::vector<ImageTriple>&,
                                             const Eigen::Isometry3d&)>& before_estimate = {});

 private:
  const RamboCell& cell_;
  const TrianglePoseEstimator& estimator_;
  double prior_max_age_s_;
  arm::Puma560 arm_;
  std::optional<std::pair<int64_t, Eigen::Isometry3d>> last_;  // newest found pose in base
};

}  // namespace ephor::rambo
