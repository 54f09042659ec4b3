#pragma once
// ephor-stripe-calibrate's messages, as its rig (BusRig in main.cc) handles
// them (out of main.cc, so that the fuzz target rig_messages_fuzz.cc runs
// what the process runs): what its ARM_STATE, MOTION_DONE and STRIPE_IMAGE
// handlers keep, the ARM_GOAL and STRIPE_CAPTURE of each view, and what a
// view's answers mean for the calibration (RigInbox). Joints in rad, PUMA 560
// order.
//
// Threading: not thread-safe; BusRig holds its mutex around every call.

#include <cstdint>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "common/arm/puma560.h"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/motion_done_t.hpp"
#include "ephor/stripe_capture_t.hpp"
#include "ephor/stripe_image_t.hpp"

namespace ephor::stripe {

class RigInbox {
 public:
  // `name`: this process's bus name, the requester its images answer.
  explicit RigInbox(std::string name) : name_(std::move(name)) {}

  // ARM_STATE: true the first time (the arm is heard).
  bool on_arm_state(const arm_state_t& m);
  // MOTION_DONE: true when it answers the goal awaited (kept as done()).
  bool on_motion_done(const motion_done_t& m);
  // STRIPE_IMAGE: true when it answers this process's request awaited (kept
  // as image()).
  bool on_image(const stripe_image_t& m);

  bool arm_heard() const { return arm_heard_; }

  // The ARM_GOAL of the next view (a joint goal to q, a new goal id), whose
  // MOTION_DONE is then awaited.
  arm_goal_t next_goal(const arm::Joints& q, int64_t utime);
  int64_t goal_id() const { return goal_id_; }
  const std::optional<motion_done_t>& done() const { return done_; }
  // With done(): true when the arm reached the view; false when it refused
  // it (out of its reach or colliding by its own checks: the view is
  // skipped). Throws CalibrationError naming the view when the move did not
  // finish.
  bool view_reached() const;

  // The view's STRIPE_CAPTURE (one request id per view: the goal id; a
  // retry asks again with the same), whose STRIPE_IMAGE is then awaited.
  stripe_capture_t next_capture(int8_t mode, int64_t utime);
  const std::optional<stripe_image_t>& image() const { return image_; }
  // With image(): its pixels, and its joint readings in *q. Throws
  // CalibrationError naming what is wrong with a bad image.
  cv::Mat view_image(arm::Joints* q) const;

 private:
  std::string name_;
  bool arm_heard_ = false;
  int64_t goals_ = 0, goal_id_ = 0, request_id_ = 0;
  std::optional<motion_done_t> done_;
  std::optional<stripe_image_t> image_;
};

}  // namespace ephor::stripe
