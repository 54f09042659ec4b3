// ephor-calibrate: the image-to-field calibration command (paper 003,
// section 5; `tools/ephor calibrate`). With a camera on CAMERA and the arm's
// servo layer on ARM_SERVO / ARM_TRAJECTORY (ephor-sim, or real hardware)
// running:
//
//   ephor-calibrate --out deploy/calibration/calibrated.pbtxt [--timeout-s 300]
//
// For each point of the CalibrationPlan: inverse kinematics nearest to the
// present joints, a slow trapezoidal joint move on ARM_TRAJECTORY (as a teach
// pendant would: the arm has no calibration yet, so ephor-arm's image-space
// commands cannot be used), wait for trajectory_done, then one camera frame
// with the tool light off and one with it on (SIM_TOOL_LIGHT: on from the
// start, off only for the dark frame); the light's
// centre in their difference and the tip's position from the measured joints
// (forward kinematics) make one correspondence. Then it fits both planes'
// maps (FieldCalibration::fit), prints the residual of every point (px and
// mm), writes the Protobuf text file with the correspondences, parks the arm
// and turns the light off. The light is turned off on every exit path.
//
// Trajectory seqs are 4e18 + wall clock us: far above ephor-arm's (which
// start at the wall clock in us), so the servo never takes one for the other.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/arm/arm_workcell.h"
#include "common/calibration/field_calibration.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/shepherd/calibrate/calibration_plan.h"
#include "common/shepherd/calibrate/joint_move.h"
#include "common/shepherd/calibrate/tool_spot_finder.h"
#include "common/time/clock.h"
#include "ephor/camera_frame_t.hpp"
#include "ephor/joint_state_t.hpp"
#include "ephor/joint_trajectory_t.hpp"
#include "ephor/shepherd_tool_light_t.hpp"
#include "procs/shepherd/calibrate/calibrate_messages.h"

namespace {

using ephor::calibration::Correspondence;
using ephor::calibration::Plane;

constexpr int64_t kSeqBase = 4'000'000'000'000'000'000;

struct Interrupted : std::runtime_error {
  Interrupted() : std::runtime_error("interrupted by a signal") {}
};

// The newest camera frame and joint state (CellInputs, written by the bus
// thread), and the tool light.
class CellLink {
 public:
  CellLink(ephor::Bus& bus) : bus_(bus) {
    bus.subscribe<ephor::camera_frame_t>(
        ephor::channels::kCamera, [this](const ephor::camera_frame_t& m) { inputs_.on_frame(m); });
    bus.subscribe<ephor::joint_state_t>(
        ephor::channels::kArmServo, [this](const ephor::joint_state_t& m) { inputs_.on_state(m); });
  }

  std::optional<ephor::joint_state_t> state() const { return inputs_.state(); }
  int64_t frame_utime() const { return inputs_.frame_utime(); }
  ephor::calibrate::GreyFrame frame() const { return inputs_.frame(); }
  int64_t bad_frames() const { return inputs_.bad_frames(); }

  void light(bool on) {
    ephor::shepherd_tool_light_t m;
    m.utime = ephor::wall_us();
    m.on = on;
    bus_.publish(ephor::channels::kSimToolLight, m);
  }

 private:
  ephor::Bus& bus_;
  ephor::calibrate::CellInputs inputs_;
};

// Turns the light off however the procedure ends.
struct LightGuard {
  CellLink& link;
  ~LightGuard() {
    for (int i = 0; i < 3; ++i) link.light(false);  // UDP: say it more than once
  }
};

using ephor::calibrate::joints_of;

class Calibrator {
 public:
  Calibrator(ephor::Bus& bus, CellLink& link, double timeout_s, double speed_fraction,
             double settle_s)
      : bus_(bus),
        link_(link),
        deadline_ns_(ephor::mono_ns() + static_cast<int64_t>(timeout_s * 1e9)),
        speed_fraction_(speed_fraction),
        settle_s_(settle_s),
        puma_(ephor::arm::make_puma(cell_)) {}

  // Polls `pred` every 10 ms until true; false after `timeout_s` (or the
  // overall deadline). Throws Interrupted on SIGINT/SIGTERM.
  bool wait(const std::function<bool()>& pred, double timeout_s) {
    const int64_t end =
        std::min(deadline_ns_, ephor::mono_ns() + static_cast<int64_t>(timeout_s * 1e9));
    while (!pred()) {
      if (ephor::mono_ns() >= end) return false;
      if (ephor::wait_for_shutdown_signal(0.01) != 0) throw Interrupted();
    }
    return true;
  }
  void pause(double s) {
    wait([] { return false; }, s);
  }

  void check_inputs(double timeout_s = 5.0) {
    if (!wait([&] { return link_.state().has_value(); }, timeout_s))
      throw std::runtime_error(
          fmt::format("no servo state on ARM_SERVO within {:.0f} s: is ephor-sim (or the arm's "
                      "servo layer) running on this LCM network?",
                      timeout_s));
    if (!wait([&] { return link_.frame_utime() != 0; }, timeout_s))
      throw std::runtime_error(
          fmt::format("no camera frames on CAMERA within {:.0f} s ({} malformed frames): is "
                      "ephor-sim (or a camera) running on this LCM network?",
                      timeout_s, link_.bad_frames()));
  }

  // Moves the tool (joint space, slowly) to `goal` and waits until the servo is done.
  void move_to(const ephor::arm::Joints& goal, const std::string& what) {
    const auto now = link_.state();
    const auto path =
        ephor::calibrate::JointMove::plan(ephor::calibrate::move_start_of(*now, puma_.limits()),
                                          goal, puma_.limits(), speed_fraction_);
    const int64_t utime = ephor::wall_us();
    ephor::joint_trajectory_t m =
        ephor::calibrate::trajectory_message_of(path, utime, kSeqBase + utime);
    const double timeout = path.duration_s() + 10.0;
    bus_.publish(ephor::channels::kArmTrajectory, m);
    int64_t resent_ns = ephor::mono_ns();
    const bool done = wait(
        [&] {
          const auto s = link_.state();
          if (s->trajectory_seq != m.seq && ephor::mono_ns() - resent_ns > 500'000'000) {
            bus_.publish(ephor::channels::kArmTrajectory, m);  // lost? the servo ignores repeats
            resent_ns = ephor::mono_ns();
          }
          if (s->trajectory_seq == m.seq && s->fault)
            throw std::runtime_error(
                fmt::format("servo fault while moving to {}: {}", what, s->fault_reason));
          return s->trajectory_seq == m.seq && s->trajectory_done;
        },
        timeout);
    if (!done) {
      const auto s = link_.state();
      throw std::runtime_error(fmt::format(
          "arm did not finish the move to {} within {:.1f} s (servo at trajectory {}, done {}, "
          "fault '{}')",
          what, timeout, s->trajectory_seq, s->trajectory_done, s->fault_reason));
    }
  }

  ephor::arm::Joints ik(const Eigen::Vector3d& tip, const std::string& what) {
    const auto goal =
        puma_.nearest_inverse(ephor::arm::tool_down_pose(cell_, tip.x(), tip.y(), tip.z(), 0.0),
                              joints_of(*link_.state()));
    if (!goal)
      throw std::runtime_error("inverse kinematics failed for " + what +
                               ": no joint solution within the limits");
    return *goal;
  }

  // The newest frame captured at least 100 ms after now, with the light as asked.
  ephor::calibrate::GreyFrame frame_with_light(bool on, const std::string& what) {
    link_.light(on);
    const int64_t after = ephor::wall_us() + 100'000;
    if (!wait([&] { return link_.frame_utime() > after; }, 3.0))
      throw std::runtime_error("no camera frame within 3 s at " + what +
                               " (camera stopped, or its clock is far behind ours)");
    return link_.frame();
  }

  int run(const std::string& out) {
    check_inputs();
    LightGuard guard{link_};
    link_.light(true);  // on throughout, off only for the dark frame at each point
    const ephor::calibrate::CalibrationPlan plan(cell_);
    const ephor::calibrate::ToolSpotFinder finder;
    std::vector<Correspondence> object, elevation;
    int index = 0;
    for (const auto& stop : plan.stops()) {
      const bool obj = stop.plane == Plane::kObject;
      const std::string what = fmt::format(
          "{} ({:.1f}, {:.1f}, {:.1f}) mm in the {} plane",
          stop.measure ? fmt::format("point {}", index + 1) : std::string("via point"),
          stop.tip_mm.x(), stop.tip_mm.y(), stop.tip_mm.z(), obj ? "object" : "elevation");
      move_to(ik(stop.tip_mm, what), what);
      if (!stop.measure) continue;
      ++index;
      pause(settle_s_);
      std::optional<ephor::calibrate::ToolSpot> spot;
      std::string why;
      Eigen::Vector3d tip = Eigen::Vector3d::Zero();
      for (int attempt = 0; attempt < 3 && !spot; ++attempt) {
        const auto q0 = joints_of(*link_.state());
        const auto dark = frame_with_light(false, what);
        const auto lit = frame_with_light(true, what);
        const auto q1 = joints_of(*link_.state());
        if ((q1 - q0).cwiseAbs().maxCoeff() > 1e-3) {
          why = "the arm moved while the frames were taken";
          continue;
        }
        const auto r = finder.find(lit, dark);
        spot = r.spot;
        why = r.reason;
        if (!spot) spdlog::warn("{}: try {} of 3: {}", what, attempt + 1, why);
        tip = ephor::arm::tool_in_field(cell_, q1).tip_mm;  // where the encoders say the tip is
      }
      if (!spot) throw std::runtime_error("light spot not found at " + what + ": " + why);
      spdlog::info("{}: spot at ({:.2f}, {:.2f}) px, tip at ({:.2f}, {:.2f}, {:.2f}) mm", what,
                   spot->centre_px.x(), spot->centre_px.y(), tip.x(), tip.y(), tip.z());
      (obj ? object : elevation).push_back({spot->centre_px, tip.head<2>()});
    }

    const auto fitted = ephor::calibration::FieldCalibration::fit(object, elevation);
    std::string table =
        "residuals (fit minus measurement):\n  plane      field x, y (mm)        image u, v (px)   "
        "   px      mm\n";
    double worst_mm = 0.0, sum2 = 0.0;
    int n = 0;
    for (const auto plane : {Plane::kObject, Plane::kElevation})
      for (const auto& c : plane == Plane::kObject ? object : elevation) {
        const double e_px =
            (fitted.field_to_image(c.field_mm.x(), c.field_mm.y(), plane) - c.image_px).norm();
        const double e_mm =
            (fitted.image_to_field(c.image_px.x(), c.image_px.y(), plane) - c.field_mm).norm();
        worst_mm = std::max(worst_mm, e_mm);
        sum2 += e_mm * e_mm;
        ++n;
        table += fmt::format("  {:9}  ({:7.1f}, {:6.1f})   ({:7.2f}, {:7.2f})   {:.3f}   {:.3f}\n",
                             plane == Plane::kObject ? "object" : "elevation", c.field_mm.x(),
                             c.field_mm.y(), c.image_px.x(), c.image_px.y(), e_px, e_mm);
      }
    const double rms_mm = std::sqrt(sum2 / n);
    std::printf("%s", table.c_str());
    std::printf("rms residual %.3f mm, worst %.3f mm over %d points\n", rms_mm, worst_mm, n);

    const std::time_t t = std::time(nullptr);
    char when[32];
    std::strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
    const std::string source = fmt::format(
        "ephor-calibrate {}: {} object-plane and {} elevation-plane points, tool light on/off "
        "differencing; rms residual {:.3f} mm, worst {:.3f} mm",
        when, object.size(), elevation.size(), rms_mm, worst_mm);
    const ephor::calibration::FieldCalibration cal(fitted.matrix(Plane::kObject),
                                                   fitted.matrix(Plane::kElevation),
                                                   fitted.planes(), object, elevation, source);
    cal.save(out, "Image-to-field calibration measured with the arm (tools/ephor calibrate).\n" +
                      source + "\nSchema: common/calibration/calibration.proto.");
    spdlog::info("wrote {}", out);

    link_.light(false);
    move_to(ephor::arm::park_joints(cell_), "the park pose");
    std::printf("calibration written to %s\n", out.c_str());
    return 0;
  }

 private:
  ephor::Bus& bus_;
  CellLink& link_;
  int64_t deadline_ns_;
  double speed_fraction_;
  double settle_s_;
  ephor::geometry::Workcell cell_;
  ephor::arm::Puma560 puma_;
};

}  // namespace

int main(int argc, char** argv) {
  ephor::block_shutdown_signals();
  CLI::App app{
      "ephor-calibrate: move the arm to points, find its tool light in the camera image, "
      "fit and save the image-to-field calibration"};
  ephor::ProcessArgs args;
  ephor::add_process_flags(app, args, "calibrate");
  std::string out;
  double timeout_s = 300.0, speed = 0.5, settle_s = 0.3;
  double probe_s = 0.0;
  app.add_option("--out", out, "calibration file to write (Protobuf text)");
  app.add_option("--probe-s", probe_s,
                 "only check for this many seconds that a camera and a servo layer are "
                 "publishing: exit 0 if so, 3 if not (tools/ephor calibrate uses it)")
      ->check(CLI::Range(0.1, 60.0));
  app.add_option("--timeout-s", timeout_s, "give up after this many seconds (default 300)")
      ->check(CLI::Range(1.0, 3600.0));
  app.add_option("--speed", speed,
                 "fraction of the joint velocity/acceleration limits (default 0.5)")
      ->check(CLI::Range(0.05, 1.0));
  app.add_option("--settle-s", settle_s, "wait after each move before the frames, s (default 0.3)")
      ->check(CLI::Range(0.0, 10.0));
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  ephor::init_logging(args.name);

  try {
    ephor::Bus bus(args.lcm_url, args.name);
    CellLink link(bus);
    bus.start();
    int rc = 1;
    try {
      Calibrator calibrator(bus, link, timeout_s, speed, settle_s);
      if (probe_s > 0.0) {
        try {
          calibrator.check_inputs(probe_s);
          rc = 0;
        } catch (const std::runtime_error& e) {
          spdlog::info("probe: {}", e.what());
          rc = 3;
        }
      } else if (out.empty()) {
        spdlog::error("--out FILE is required");
        rc = 2;
      } else {
        rc = calibrator.run(out);
      }
    } catch (const std::exception& e) {
      for (int i = 0; i < 3; ++i) link.light(false);
      spdlog::error("calibration failed: {}", e.what());
      rc = 1;
    }
    bus.stop();
    return rc;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
