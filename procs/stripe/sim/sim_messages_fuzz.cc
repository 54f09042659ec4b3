// Fuzz target (issue 18): ephor-stripe-sim's handlers and tasks on any
// interleaved stream of ARM_TRAJECTORY and STRIPE_CAPTURE messages, with its
// tasks released as the runtime would: each message decoded as the bus does
// (one that does not decode to its full size is dropped) and handed to its
// handler (SimServo::on_trajectory, CaptureDesk::on_capture); the physics
// task at every 2 ms boundary of a fake monotonic clock advanced by each
// record's step (the servo stepped to it, ARM_SERVO every other tick); the
// camera task on a record of channel 2 and at the end: each request waiting
// answered again when it repeats its requester's last, else taken once the
// arm is at rest or the process's --settle-ms 300 passed (the fake clock and
// the physics task run meanwhile), the image rendered by the ideal robot's
// StripeWorld on the empty table of deploy/stripe/workcell.pbtxt, and its
// STRIPE_IMAGE, STRIPE_CAMERA and STRIPE_TRUTH built. Rendering dominates a
// run, so at most kMaxRendered images are rendered per input; later ones are
// a blank image of the same size (their messages are checked alike).
//
// Checked: a refused trajectory or capture comes with its reason, and
// captures only for an unknown mode; at most 16 requests wait and 16
// requesters' answers are kept; ARM_SERVO (sim::to_joint_state) finite,
// within the PUMA 560's joint limits (the servo's promise whatever the
// trajectory) and encodes; every STRIPE_IMAGE answers its request (requester,
// request id, scan, stripe, mode), is an image the processes that read it
// accept (image_of()), with readings within the joint limits; a repeat is
// the answer given before; STRIPE_CAMERA carries the same pixels;
// STRIPE_TRUTH finite; each encodes.
//
// Input: a FuzzMessageStream (common/fuzz/fuzz_input.h) of up to 256
// messages of up to 4096 bytes; channels 0 ARM_TRAJECTORY
// (joint_trajectory_t), 1 STRIPE_CAPTURE (stripe_capture_t), 2 run the
// camera task. Seeds: fuzz_corpus/stripe_sim (a move to a view, then a
// stripe and a spot image; a repeated request and two requesters; refused
// trajectories and an unknown mode; a capture while the arm moves).
//
// STRIPE_SIM_FUZZ_TRACE=1 in the environment prints what is refused, the
// servo's faults and each image taken (for writing seeds).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "common/arm/arm_workcell.h"
#include "common/arm/servo_messages.h"
#include "common/config/repo_paths.h"
#include "common/fuzz/fuzz_input.h"
#include "common/geometry/workcell_file.h"
#include "common/stripe/stripe_messages.h"
#include "common/stripe/stripe_world.h"
#include "procs/stripe/sim/sim_messages.h"

namespace {

using namespace ephor;
using namespace ephor::stripe;

constexpr int64_t kPhysicsNs = 2'000'000;   // the physics task's period
constexpr int64_t kSettleNs = 300'000'000;  // --settle-ms 300
constexpr int64_t kWallStartUs = 1'700'000'000'000'000;
constexpr int kMaxRendered = 4;  // images rendered per input

struct World {
  geometry::Workcell workcell;
  StripeScene scene;
  StripeWorld world;
  arm::JointLimits limits;
  World()
      : workcell(geometry::load_workcell_file(resolve_repo_path("deploy/stripe/workcell.pbtxt"))),
        world(scene, StripeWorkcell::from_workcell(workcell), RobotTruth::ideal()),
        limits(arm::make_puma(workcell).limits()) {}
};

const World& world() {
  static const World w;
  return w;
}

class Sim {
 public:
  Sim() : servo_(world().limits), trace_(std::getenv("STRIPE_SIM_FUZZ_TRACE") != nullptr) {}

  void trajectory(const joint_trajectory_t& m) {
    std::string why;
    if (servo_.on_trajectory(m, &why)) return;
    if (why.empty()) fuzz::fail("a trajectory refused without a reason");
    if (trace_)
      std::fprintf(stderr, "trajectory %lld refused: %s\n", static_cast<long long>(m.seq),
                   why.c_str());
  }

  void capture(const stripe_capture_t& m) {
    std::string why;
    const bool taken = desk_.on_capture(m, &why);
    const bool known =
        m.mode == stripe_capture_t::MODE_STRIPE || m.mode == stripe_capture_t::MODE_SPOT;
    if (taken != known)
      fuzz::fail("a capture of mode " + std::to_string(m.mode) + " " +
                 (taken ? "taken" : "refused"));
    if (!taken && why.empty()) fuzz::fail("a capture refused without a reason");
    if (!taken && trace_) std::fprintf(stderr, "capture refused: %s\n", why.c_str());
    if (desk_.waiting() > CaptureDesk::kQueued) fuzz::fail("more requests waiting than kept");
  }

  // The clock moves by dt_ns; the physics task runs at each of its boundaries.
  void run_for(int64_t dt_ns) {
    const int64_t end = now_ns_ + dt_ns;
    while (next_physics_ns_ <= end) {
      now_ns_ = next_physics_ns_;
      next_physics_ns_ += kPhysicsNs;
      physics();
    }
    now_ns_ = end;
  }

  void camera() {
    for (;;) {
      std::optional<stripe_capture_t> req = desk_.next();
      if (!req) return;
      if (const stripe_image_t* again = desk_.repeat_of(*req)) {
        if (again->requester != req->header.sender || again->request_id != req->request_id)
          fuzz::fail("a repeat answered with another request's image");
        fuzz::check_encodes(*again, "a repeated STRIPE_IMAGE");
        continue;
      }
      const int64_t give_up = now_ns_ + kSettleNs;
      for (;;) {
        servo_.advance_to(seconds());
        if (servo_.at_rest() || now_ns_ >= give_up) break;
        run_for(1'000'000);
      }
      const arm::Joints q = servo_.state().q;
      const int64_t index = images_++;
      const cv::Mat img =
          index >= kMaxRendered ? cv::Mat(256, 256, CV_8UC1, cv::Scalar(0))
          : req->mode == stripe_capture_t::MODE_SPOT
              ? world().world.spot_image(q, 1000003ULL + static_cast<uint64_t>(index))
              : world().world.image(q, 1000003ULL + static_cast<uint64_t>(index));
      const int64_t utime = kWallStartUs + now_ns_ / 1000;
      const stripe_image_t m = image_message_of(*req, img, q, utime, index);
      if (trace_)
        std::fprintf(stderr, "image %lld for %s %lld at %.3f s, %s, servo %s\n",
                     static_cast<long long>(index), req->header.sender.c_str(),
                     static_cast<long long>(req->request_id), seconds(),
                     servo_.at_rest() ? "at rest" : "moving",
                     servo_.state().fault ? servo_.state().fault_reason.c_str() : "ok");
      check_image(m, *req);
      const camera_frame_t frame = camera_frame_of(m);
      if (frame.width != m.width || frame.height != m.height || frame.data != m.data ||
          frame.size != m.size || frame.frame_index != index)
        fuzz::fail("STRIPE_CAMERA is not the image's pixels");
      fuzz::check_encodes(frame, "STRIPE_CAMERA");
      const stripe_truth_t t = truth_message(world().world, 0, "", q, utime, index);
      if (!fuzz::all_finite(t.q, 6) || !fuzz::all_finite(t.flange_r, 9) ||
          !fuzz::all_finite(t.flange_t_mm, 3) || !fuzz::all_finite(t.camera_in_flange_r, 9) ||
          !fuzz::all_finite(t.projector_in_flange_t_mm, 3) || !fuzz::all_finite(t.dh_error, 18) ||
          !std::isfinite(t.fx_px) || !std::isfinite(t.cx_px))
        fuzz::fail("a STRIPE_TRUTH that is not finite");
      fuzz::check_encodes(t, "STRIPE_TRUTH");
      desk_.answered(m);
      if (desk_.requesters() > CaptureDesk::kRequestersKept)
        fuzz::fail("answers kept for more requesters than kRequestersKept");
      if (desk_.repeat_of(*req) == nullptr) fuzz::fail("the answer just given not kept");
    }
  }

 private:
  double seconds() const { return static_cast<double>(now_ns_) * 1e-9; }

  void physics() {
    servo_.advance_to(seconds());
    if (!servo_.servo_tick()) return;
    const joint_state_t m = sim::to_joint_state(servo_.state(), kWallStartUs + now_ns_ / 1000);
    if (!fuzz::all_finite(m.q, 6) || !fuzz::all_finite(m.qd, 6))
      fuzz::fail("an ARM_SERVO that is not finite");
    const arm::JointLimits& limits = world().limits;
    if (!limits.within(joints_of(m.q), 1e-6))
      fuzz::fail("ARM_SERVO joints outside the joint limits");
    for (int j = 0; j < 6; ++j)
      if (std::abs(m.qd[j]) > limits.qd_max[j] * (1.0 + 1e-6))
        fuzz::fail("ARM_SERVO joint " + std::to_string(j + 1) + " faster than its limit");
    fuzz::check_encodes(m, "ARM_SERVO");
  }

  void check_image(const stripe_image_t& m, const stripe_capture_t& req) const {
    if (m.requester != req.header.sender || m.request_id != req.request_id ||
        m.scan_id != req.scan_id || m.stripe_index != req.stripe_index || m.mode != req.mode)
      fuzz::fail("a STRIPE_IMAGE that does not answer its request");
    std::string why;
    if (image_of(m, &why).empty()) fuzz::fail("a STRIPE_IMAGE its readers refuse: " + why);
    if (!world().limits.within(joints_of(m.q), 1e-6))
      fuzz::fail("an image taken at joints outside the limits");
    fuzz::check_encodes(m, "STRIPE_IMAGE");
  }

  SimServo servo_;
  CaptureDesk desk_;
  int64_t now_ns_ = 0;
  int64_t next_physics_ns_ = kPhysicsNs;
  int64_t images_ = 0;
  bool trace_ = false;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Sim sim;
  fuzz::FuzzMessageStream stream(data, size, 3);
  fuzz::FuzzMessage msg;
  while (stream.next(msg)) {
    sim.run_for(msg.step_us * 1000);
    if (msg.channel == 0) {
      joint_trajectory_t m;
      if (msg.decode(m)) sim.trajectory(m);
    } else if (msg.channel == 1) {
      stripe_capture_t m;
      if (msg.decode(m)) sim.capture(m);
    } else {
      sim.camera();
    }
  }
  sim.camera();
  return 0;
}
