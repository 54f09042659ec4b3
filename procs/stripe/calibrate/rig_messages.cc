#include "procs/stripe/calibrate/rig_messages.h"

#include <string>

#include "common/stripe/sensor_calibrator.h"
#include "common/stripe/stripe_messages.h"

namespace ephor::stripe {

bool RigInbox::on_arm_state(const arm_state_t&) {
  if (arm_heard_) return false;
  arm_heard_ = true;
  return true;
}

bool RigInbox::on_motion_done(const motion_done_t& m) {
  if (m.goal_id != goal_id_) return false;
  done_ = m;
  return true;
}

bool RigInbox::on_image(const stripe_image_t& m) {
  if (m.requester != name_ || m.request_id != request_id_) return false;
  image_ = m;
  return true;
}

arm_goal_t RigInbox::next_goal(const arm::Joints& q, int64_t utime) {
  goal_id_ = ++goals_;
  done_.reset();
  arm_goal_t g{};
  g.utime = utime;
  g.goal_id = goal_id_;
  g.kind = arm_goal_t::KIND_JOINTS;
  set_joints(q, g.joints_rad);
  g.target_object = -1;
  return g;
}

bool RigInbox::view_reached() const {
  if (!done_) throw CalibrationError("no MOTION_DONE for view " + std::to_string(goal_id_));
  if (done_->status == motion_done_t::STATUS_REJECTED) return false;
  if (done_->status != motion_done_t::STATUS_DONE)
    throw CalibrationError("the arm did not finish the move to view " + std::to_string(goal_id_) +
                           ": " + done_->reason);
  return true;
}

stripe_capture_t RigInbox::next_capture(int8_t mode, int64_t utime) {
  request_id_ = goal_id_;  // one capture per view
  image_.reset();
  stripe_capture_t c{};
  c.utime = utime;
  c.request_id = request_id_;
  c.scan_id = 0;
  c.stripe_index = -1;
  c.mode = mode;
  return c;
}

cv::Mat RigInbox::view_image(arm::Joints* q) const {
  if (!image_) throw CalibrationError("no image for view " + std::to_string(goal_id_));
  std::string why;
  cv::Mat img = image_of(*image_, &why);
  if (img.empty()) throw CalibrationError("a bad image from the camera: " + why);
  if (q != nullptr) *q = joints_of(image_->q);
  return img;
}

}  // namespace ephor::stripe
