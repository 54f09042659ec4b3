// Fuzz target (issue 18): ephor-stripe-calibrate's handlers (ARM_STATE,
// MOTION_DONE, STRIPE_IMAGE; BusRig in main.cc) on any interleaved stream of
// those messages, with the rig's steps between them as BusRig::take() makes
// them for each view: each message decoded as the bus does (one that does
// not decode to its full size is dropped) and handed to RigInbox; on a
// record of channel 3 the rig goes on: with no view under way, the next
// view's ARM_GOAL (the work cell's reference joints, a stripe or a spot
// image by the record's first byte); with its MOTION_DONE in, view_reached()
// (a refused view is skipped, a move that did not finish ends the
// calibration with a CalibrationError) and the view's STRIPE_CAPTURE; with
// its STRIPE_IMAGE in, view_image() as the fits take it (a bad image ends
// the calibration); without, the capture again, at most 10 times. A
// calibration that ends starts over with the next view. What the fits do
// with the pixels (find_spot, the extractor) is the target stripe_image's.
//
// Checked: the arm is heard on the first ARM_STATE only; a MOTION_DONE is
// kept only for the goal awaited, a STRIPE_IMAGE only for this process's
// request awaited; goal ids increase from 1, the capture's request id is its
// view's; a view image is 8-bit, one channel, its message's size, with
// finite joint readings (the fits' input); a CalibrationError names the
// problem; ARM_GOAL and STRIPE_CAPTURE encode.
//
// Input: a FuzzMessageStream (common/fuzz/fuzz_input.h) of up to 256
// messages of up to 4096 bytes; channels 0 ARM_STATE (arm_state_t), 1
// MOTION_DONE (motion_done_t), 2 STRIPE_IMAGE (stripe_image_t), 3 the rig's
// next step. Seeds: fuzz_corpus/stripe_calibrate (two views answered, a
// stripe and a spot image; a view refused, one failed, an image for another
// requester and a stale one; a capture asked again, a bad image).
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "common/fuzz/fuzz_input.h"
#include "common/stripe/scan_geometry.h"
#include "common/stripe/sensor_calibrator.h"
#include "procs/stripe/calibrate/rig_messages.h"

namespace {

using namespace ephor;
using namespace ephor::stripe;

constexpr const char* kName = "calibrate";  // the process's default --name
constexpr int kCaptures = 10;               // BusRig::take()'s attempts

void check_error(const CalibrationError& e) {
  if (std::string(e.what()).empty()) fuzz::fail("a CalibrationError without a message");
}

class Rig {
 public:
  void arm_state(const arm_state_t& m) {
    const bool heard = inbox_.arm_heard();
    if (inbox_.on_arm_state(m) == heard) fuzz::fail("the arm heard other than on its first state");
    if (!inbox_.arm_heard()) fuzz::fail("the arm not heard after its state");
  }

  void motion_done(const motion_done_t& m) {
    const bool kept = inbox_.on_motion_done(m);
    if (kept != (m.goal_id == inbox_.goal_id()))
      fuzz::fail("MOTION_DONE for goal " + std::to_string(m.goal_id) + (kept ? " kept" : " lost") +
                 " while awaiting " + std::to_string(inbox_.goal_id()));
  }

  void image(const stripe_image_t& m) {
    const bool ours = m.requester == kName && m.request_id == request_id_;
    if (inbox_.on_image(m) != ours)
      fuzz::fail("STRIPE_IMAGE for " + m.requester + " request " + std::to_string(m.request_id) +
                 (ours ? " lost" : " kept"));
  }

  void step(uint8_t how) {
    if (!view_) {
      const arm::Joints q = StripeWorkcell::reference_joints();
      const arm_goal_t g = inbox_.next_goal(q, 1'700'000'000'000'000);
      if (g.goal_id != ++goals_ || inbox_.goal_id() != goals_) fuzz::fail("goal ids out of order");
      if (g.kind != arm_goal_t::KIND_JOINTS) fuzz::fail("an ARM_GOAL that is not a joint goal");
      if (inbox_.done()) fuzz::fail("an old MOTION_DONE taken for the new goal");
      fuzz::check_encodes(g, "ARM_GOAL");
      view_ = true;
      mode_ = (how & 1) != 0 ? stripe_capture_t::MODE_SPOT : stripe_capture_t::MODE_STRIPE;
      captures_ = 0;
      return;
    }
    if (captures_ == 0) {
      if (!inbox_.done()) return;  // still waiting for the arm
      try {
        if (!inbox_.view_reached()) {
          view_ = false;  // skipped
          return;
        }
      } catch (const CalibrationError& e) {
        check_error(e);
        if (inbox_.done()->status == motion_done_t::STATUS_DONE)
          fuzz::fail("a finished move taken as failed");
        view_ = false;  // the calibration ends; the next input's would start over
        return;
      }
      if (inbox_.done()->status != motion_done_t::STATUS_DONE)
        fuzz::fail("a move that did not finish taken as done");
      capture();
      return;
    }
    if (!inbox_.image()) {
      if (captures_ >= kCaptures) {
        view_ = false;  // "no image from the camera ... after 10 requests"
        return;
      }
      capture();
      return;
    }
    arm::Joints q = arm::Joints::Constant(std::numeric_limits<double>::quiet_NaN());
    try {
      const cv::Mat img = inbox_.view_image(&q);
      const stripe_image_t& m = *inbox_.image();
      if (img.empty() || img.type() != CV_8UC1 || img.cols != m.width || img.rows != m.height ||
          img.total() != m.data.size())
        fuzz::fail("a view image that is not the message's 8-bit pixels");
      if (!q.allFinite()) fuzz::fail("view joint readings that are not finite");
    } catch (const CalibrationError& e) {
      check_error(e);
    }
    view_ = false;
  }

 private:
  void capture() {
    const stripe_capture_t c = inbox_.next_capture(mode_, 1'700'000'000'000'000);
    request_id_ = c.request_id;
    if (c.request_id != goals_) fuzz::fail("a capture whose request id is not its view's");
    if (inbox_.image()) fuzz::fail("an old image taken for the new request");
    fuzz::check_encodes(c, "STRIPE_CAPTURE");
    ++captures_;
  }

  RigInbox inbox_{kName};
  int64_t goals_ = 0, request_id_ = 0;
  bool view_ = false;
  int8_t mode_ = stripe_capture_t::MODE_STRIPE;
  int captures_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Rig rig;
  fuzz::FuzzMessageStream stream(data, size, 4);
  fuzz::FuzzMessage msg;
  while (stream.next(msg)) {
    switch (msg.channel) {
      case 0: {
        arm_state_t m;
        if (msg.decode(m)) rig.arm_state(m);
        break;
      }
      case 1: {
        motion_done_t m;
        if (msg.decode(m)) rig.motion_done(m);
        break;
      }
      case 2: {
        stripe_image_t m;
        if (msg.decode(m)) rig.image(m);
        break;
      }
      default:
        rig.step(msg.size > 0 ? msg.bytes[0] : 0);
        break;
    }
  }
  return 0;
}
