#pragma once
// ephor-stripe-sim's handling of its messages, as its handlers and tasks do
// it (out of main.cc, so that the fuzz target sim_messages_fuzz.cc runs what
// the process runs): an ARM_TRAJECTORY taken by the simulated servo layer
// (SimServo, stepped in 1 ms steps to the process's clock), a
// STRIPE_CAPTURE queued for the camera task (CaptureDesk, which also keeps
// each requester's last answer for a repeated request), and the
// STRIPE_IMAGE, STRIPE_CAMERA and STRIPE_TRUTH messages of an image. Joint
// readings in rad, PUMA 560 order; poses in mm, table frame.
//
// Threading: none of these is thread-safe; main.cc holds a mutex around each.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "common/arm/arm_servo.h"
#include "common/arm/puma560.h"
#include "common/stripe/stripe_world.h"
#include "ephor/camera_frame_t.hpp"
#include "ephor/joint_trajectory_t.hpp"
#include "ephor/stripe_capture_t.hpp"
#include "ephor/stripe_image_t.hpp"
#include "ephor/stripe_truth_t.hpp"

namespace ephor::stripe {

// The PUMA 560's servo layer in real time, from the light-stripe work cell's
// reference joints.
class SimServo {
 public:
  static constexpr double kStepS = 0.001;     // the servo's step
  static constexpr double kMaxLagS = 0.5;     // further behind the clock: skip ahead
  static constexpr double kRestRad_s = 1e-4;  // every joint slower: at rest, an image may be taken

  explicit SimServo(const arm::JointLimits& limits);

  // An ARM_TRAJECTORY, taken at the next step (a newer one replaces it);
  // false and *why when sim::to_trajectory() refuses it.
  bool on_trajectory(const joint_trajectory_t& m, std::string* why);

  // Steps up to now_s (seconds of the process's clock since it started);
  // more than kMaxLagS behind, it skips ahead (logged) instead of catching up.
  void advance_to(double now_s);

  // The physics task's 2 ms tick: true every other one (ARM_SERVO at 250 Hz).
  bool servo_tick() { return ++ticks_ % 2 == 0; }

  const sim::ServoState& state() const { return servo_.state(); }
  const arm::JointLimits& limits() const { return servo_.limits(); }
  bool at_rest() const;

 private:
  sim::ArmServo servo_;
  std::optional<sim::JointTrajectory> pending_;
  double clock_s_ = 0.0;
  int ticks_ = 0;
};

// The camera's requests (STRIPE_CAPTURE) waiting for the camera task, the
// newest kQueued kept, and the last answer given to each requester, for the
// newest kRequestersKept requesters answered (the others' repeats get a new
// image).
class CaptureDesk {
 public:
  static constexpr size_t kQueued = 16;
  static constexpr size_t kRequestersKept = 16;

  // Queues a request; false and *why for an unknown mode (nothing queued).
  bool on_capture(const stripe_capture_t& m, std::string* why);
  // The oldest request waiting, taken off the queue.
  std::optional<stripe_capture_t> next();
  // The answer given to this request already (same requester and request
  // id as that requester's last), or nullptr.
  const stripe_image_t* repeat_of(const stripe_capture_t& request) const;
  // Remembers the answer to its requester's request.
  void answered(const stripe_image_t& m);

  size_t waiting() const { return requests_.size(); }
  size_t requesters() const { return last_answer_.size(); }

 private:
  std::deque<stripe_capture_t> requests_;
  std::map<std::string, stripe_image_t> last_answer_;  // per requester
  std::deque<std::string> answer_order_;               // requesters, least recently answered first
};

// The STRIPE_IMAGE answering `request`: the image `img` (8-bit, one
// channel) taken at joint readings q, utime and its index.
stripe_image_t image_message_of(const stripe_capture_t& request, const cv::Mat& img,
                                const arm::Joints& q, int64_t utime, int64_t image_index);
// The same pixels as the page's STRIPE_CAMERA frame.
camera_frame_t camera_frame_of(const stripe_image_t& m);
// STRIPE_TRUTH at joint readings q: the world's robot, cage and camera as
// they are; image_index -1 for the 1 Hz message.
stripe_truth_t truth_message(const StripeWorld& world, int robot_seed, const std::string& scene,
                             const arm::Joints& q, int64_t utime, int64_t image_index);

}  // namespace ephor::stripe
