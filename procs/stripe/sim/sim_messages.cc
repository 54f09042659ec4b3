#include "procs/stripe/sim/sim_messages.h"

#include <algorithm>
#include <utility>

#include <spdlog/spdlog.h>

#include "common/arm/servo_messages.h"
#include "common/stripe/stripe_messages.h"

namespace ephor::stripe {

SimServo::SimServo(const arm::JointLimits& limits)
    : servo_(limits, StripeWorkcell::reference_joints()) {}

bool SimServo::on_trajectory(const joint_trajectory_t& m, std::string* why) {
  std::string reason;
  auto t = sim::to_trajectory(m, reason);
  if (!t) {
    if (why) *why = reason;
    return false;
  }
  pending_ = std::move(*t);
  return true;
}

void SimServo::advance_to(double now_s) {
  if (now_s - clock_s_ > kMaxLagS) {
    spdlog::warn("servo {:.3f} s behind the clock; skipping ahead", now_s - clock_s_);
    clock_s_ = now_s - kStepS;
  }
  while (clock_s_ + kStepS <= now_s) {
    if (pending_) {
      servo_.follow(*pending_);
      pending_.reset();
    }
    servo_.step(kStepS);
    clock_s_ += kStepS;
  }
}

bool SimServo::at_rest() const { return state().qd.cwiseAbs().maxCoeff() < kRestRad_s; }

bool CaptureDesk::on_capture(const stripe_capture_t& m, std::string* why) {
  if (m.mode != stripe_capture_t::MODE_STRIPE && m.mode != stripe_capture_t::MODE_SPOT) {
    if (why) *why = "unknown mode " + std::to_string(m.mode);
    return false;
  }
  if (requests_.size() >= kQueued) requests_.pop_front();
  requests_.push_back(m);
  return true;
}

std::optional<stripe_capture_t> CaptureDesk::next() {
  if (requests_.empty()) return std::nullopt;
  stripe_capture_t r = std::move(requests_.front());
  requests_.pop_front();
  return r;
}

const stripe_image_t* CaptureDesk::repeat_of(const stripe_capture_t& request) const {
  const auto it = last_answer_.find(request.header.sender);
  if (it == last_answer_.end() || it->second.request_id != request.request_id) return nullptr;
  return &it->second;
}

void CaptureDesk::answered(const stripe_image_t& m) {
  last_answer_[m.requester] = m;
  answer_order_.erase(std::remove(answer_order_.begin(), answer_order_.end(), m.requester),
                      answer_order_.end());
  answer_order_.push_back(m.requester);
  while (answer_order_.size() > kRequestersKept) {
    last_answer_.erase(answer_order_.front());
    answer_order_.pop_front();
  }
}

stripe_image_t image_message_of(const stripe_capture_t& request, const cv::Mat& img,
                                const arm::Joints& q, int64_t utime, int64_t image_index) {
  stripe_image_t m;
  m.utime = utime;
  m.requester = request.header.sender;
  m.request_id = request.request_id;
  m.scan_id = request.scan_id;
  m.stripe_index = request.stripe_index;
  m.mode = request.mode;
  m.image_index = image_index;
  set_joints(q, m.q);
  m.width = img.cols;
  m.height = img.rows;
  m.size = static_cast<int32_t>(img.total());
  m.data.assign(img.data, img.data + img.total());
  return m;
}

camera_frame_t camera_frame_of(const stripe_image_t& m) {
  camera_frame_t frame;
  frame.utime = m.utime;
  frame.frame_index = m.image_index;
  frame.width = m.width;
  frame.height = m.height;
  frame.size = m.size;
  frame.data = m.data;
  return frame;
}

stripe_truth_t truth_message(const StripeWorld& world, int robot_seed, const std::string& scene,
                             const arm::Joints& q, int64_t utime, int64_t image_index) {
  stripe_truth_t t{};
  t.utime = utime;
  t.image_index = image_index;
  t.robot_seed = robot_seed;
  t.scene = scene;
  set_joints(q, t.q);
  const RobotTruth& truth = world.truth();
  set_joints(truth.arm.errors().zero_offset_rad, t.zero_offset_rad);
  for (int j = 0; j < 6; ++j) {
    t.dh_error[3 * j] = truth.arm.errors().dh_error[static_cast<size_t>(j)].d_mm;
    t.dh_error[3 * j + 1] = truth.arm.errors().dh_error[static_cast<size_t>(j)].a_mm;
    t.dh_error[3 * j + 2] = truth.arm.errors().dh_error[static_cast<size_t>(j)].alpha_rad;
  }
  set_pose(world.flange_in_table(q), t.flange_r, t.flange_t_mm);
  set_pose(truth.cage.camera_in_flange, t.camera_in_flange_r, t.camera_in_flange_t_mm);
  set_pose(truth.cage.projector_in_flange, t.projector_in_flange_r, t.projector_in_flange_t_mm);
  t.fx_px = truth.cage.camera.fx_px;
  t.fy_px = truth.cage.camera.fy_px;
  t.cx_px = truth.cage.camera.cx_px;
  t.cy_px = truth.cage.camera.cy_px;
  return t;
}

}  // namespace ephor::stripe
