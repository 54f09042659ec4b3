// Fuzz target (issue 18): ephor-stripe-planner on any stream of what it
// subscribes to (ARM_STATE, MOTION_DONE, STRIPE_IMAGE, STRIPE_POINTS,
// STRIPE_PROFILE, STRIPE_CLOUD) with a clock: each message decoded the way
// the bus does (a message that does not decode to its full size is
// dropped), taken by its handler (arm_joints_of(): non-finite joints
// ignored; event_of(): an image only when the requester is "planner"), and
// the plan task (PlanTask, the process's own) run after each at the
// message's time: a scan planned from where the arm is (plan_raster() with
// the process's defaults, deploy/stripe/workcell.pbtxt and the drawing's
// calibration), each event through apply_event() into the ScanSequencer, its tick, the scan's
// end, the pause and the next scan; every answer as goal_message_of(),
// capture_message_of() and scan_message_of() publish it.
// A goal must be finite, within the PUMA's joint limits and the planned
// (reachable, collision-checked) goal of its stripe, its id never sent
// before; a capture a stripe of the plan or the probe, its request id new or
// the one asked last; the scan's counts within the plan; every message must
// encode.
//
// Input: one byte of options (bit 0: --region -20,-20,20,20 instead of the
// default -200,-200,200,200, so a whole scan fits a seed; bit 1: --scans 0,
// scan again and again; bit 2: --speed-mm-s 100), then up to 256 records,
// each a byte naming the channel (its value mod 7: ARM_STATE, MOTION_DONE,
// STRIPE_IMAGE, STRIPE_POINTS, STRIPE_PROFILE, STRIPE_CLOUD, or none: the
// 100 ms tick), two bytes of clock step (ms, little-endian), a 2-byte
// little-endian length and that many bytes. Ids count up from the wall
// clock at the start, 1'700'000'000'000'000 us here; the scan id is the
// wall clock at the scan's start (that plus the clock).
// Seeds: fuzz_corpus/stripe_planner (the small region's scan through
// probe, goals, images, points and cloud to done; a goal refused and one
// failed; a capture timing out; an arm state not finite).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include "common/arm/arm_workcell.h"
#include "common/config/repo_paths.h"
#include "common/fuzz/fuzz_input.h"
#include "common/geometry/workcell_file.h"
#include "common/stripe/calibration_file.h"
#include "procs/stripe/planner/plan_task.h"
#include "procs/stripe/planner/planner_messages.h"
#include "procs/stripe/planner/raster_plan.h"
#include "procs/stripe/planner/scan_sequencer.h"

namespace {

using namespace ephor;
using namespace ephor::stripe;

constexpr int64_t kStartWallUs = 1'700'000'000'000'000;

struct Setup {
  geometry::Workcell workcell;
  StripeCalibration calibration;
  arm::JointLimits limits;
};

const Setup& setup() {
  static const Setup s = [] {
    Setup out;
    out.workcell = geometry::load_workcell_file(resolve_repo_path("deploy/stripe/workcell.pbtxt"));
    out.calibration = calibration_from_flags("", 0);
    out.limits = arm::make_puma(out.workcell).limits();
    return out;
  }();
  return s;
}

// plan_raster() is pure and takes milliseconds: the plans met so far, by
// region and start joints (bit for bit), or the reason one could not be made
// (thrown again as the PlanError plan_raster() threw; main.cc: logged, exit 1).
RasterPlan plan_from(const RasterSpec& spec, bool small, const arm::Joints& q) {
  static std::map<std::vector<double>, std::variant<RasterPlan, std::string>> cache;
  std::vector<double> key(q.data(), q.data() + 6);
  key.push_back(small ? 1.0 : 0.0);
  auto it = cache.find(key);
  if (it == cache.end()) {
    if (cache.size() > 4096) cache.clear();
    std::variant<RasterPlan, std::string> made;
    try {
      made = plan_raster(spec, setup().workcell, setup().calibration.arm_model(),
                         setup().calibration.sensor, q);
    } catch (const PlanError& e) {
      made = std::string(e.what());
    }
    it = cache.emplace(key, std::move(made)).first;
  }
  if (const auto* why = std::get_if<std::string>(&it->second)) throw PlanError(*why);
  return std::get<RasterPlan>(it->second);
}

// The plan task's answers, checked.
class CheckedOutputs : public PlanOutputs {
 public:
  const PlanTask* task = nullptr;

  void goal(const GoalAction& g, arm_goal_t m) override {
    const RasterPlan& plan = task->plan();
    if (g.stripe < 0 || g.stripe >= static_cast<int>(plan.goals.size()))
      fuzz::fail("a goal for a stripe not planned");
    if (!g.q.allFinite()) fuzz::fail("a goal that is not finite");
    if (!setup().limits.within(g.q)) fuzz::fail("a goal outside the joint limits");
    if (g.q != plan.goals[static_cast<size_t>(g.stripe)])
      fuzz::fail("a goal that is not its stripe's planned one");
    if (!goal_ids_.insert(g.goal_id).second) fuzz::fail("a goal id sent twice");
    if (m.kind != arm_goal_t::KIND_JOINTS || !(m.max_speed_mm_s >= 0.0f))
      fuzz::fail("a goal message of the wrong kind or speed");
    fuzz::check_encodes(m, "ARM_GOAL");
  }

  void capture(const CaptureAction& c, stripe_capture_t m) override {
    if (c.stripe < -1 || c.stripe >= static_cast<int>(task->plan().goals.size()))
      fuzz::fail("a capture for a stripe not planned");
    if (c.request_id < last_request_) fuzz::fail("a capture's request id went back");
    last_request_ = c.request_id;
    if ((c.stripe < 0) != (m.scan_id == 0)) fuzz::fail("a capture in the wrong scan");
    fuzz::check_encodes(m, "STRIPE_CAPTURE");
  }

  void scan(stripe_scan_t m) override {
    if (m.stripes_planned != static_cast<int>(task->plan().goals.size()) ||
        m.stripes_captured < 0 || m.stripes_captured > m.stripes_planned || m.stripes_skipped < 0 ||
        m.stripes_skipped > m.stripes_planned)
      fuzz::fail("STRIPE_SCAN's counts outside the plan");
    if (!std::isfinite(m.elapsed_s) || !std::isfinite(m.stripes_per_s) ||
        !(m.motion_s >= 0.0 && std::isfinite(m.motion_s)) || m.cloud_points < 0)
      fuzz::fail("STRIPE_SCAN's times or rates not finite");
    fuzz::check_encodes(m, "STRIPE_SCAN");
  }

 private:
  std::set<int64_t> goal_ids_;
  int64_t last_request_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  int64_t now_ms = 1'000'000;  // the process's monotonic clock
  // main.cc's defaults.
  PlanTaskConfig config;
  parse_region("-200,-200,200,200", config.spec);
  config.spec.pass_length_mm = 60.0;
  const bool small = (data[0] & 1) != 0;
  if (small) parse_region("-20,-20,20,20", config.spec);
  if ((data[0] & 2) != 0) config.scans = 0;
  if ((data[0] & 4) != 0) config.speed_mm_s = 100.0;
  config.plan = [spec = config.spec, small](const arm::Joints& from) {
    return plan_from(spec, small, from);
  };
  config.wall_us = [&now_ms] { return kStartWallUs + now_ms * 1000; };
  config.calibration_name = "drawing";
  CheckedOutputs outputs;
  PlanTask task(std::move(config), outputs, kStartWallUs);
  outputs.task = &task;
  // What the handlers keep between runs of the task.
  std::optional<arm::Joints> arm_q;
  bool arm_moving = false;
  std::vector<PlanEvent> events;
  size_t at = 1;
  for (int k = 0; k < 256 && at + 5 <= size && !task.finished(); ++k) {
    const int channel = data[at] % 7;
    now_ms += data[at + 1] | (data[at + 2] << 8);
    const size_t len = data[at + 3] | (static_cast<size_t>(data[at + 4]) << 8);
    at += 5;
    if (len > size - at) break;
    const int n = static_cast<int>(len);
    const uint8_t* bytes = data + at;
    at += len;
    bool decoded = true;
    switch (channel) {
      case 0: {
        arm_state_t m;
        decoded = m.decode(bytes, 0, n) == n;
        if (decoded) {
          if (const auto q = arm_joints_of(m)) {
            if (!q->allFinite()) fuzz::fail("non-finite joints taken");
            arm_q = *q;
            arm_moving = m.moving;
          }
        }
        break;
      }
      case 1: {
        motion_done_t m;
        decoded = m.decode(bytes, 0, n) == n;
        if (decoded) events.push_back(event_of(m));
        break;
      }
      case 2: {
        stripe_image_t m;
        decoded = m.decode(bytes, 0, n) == n;
        if (decoded)
          if (auto e = event_of(m, "planner")) events.push_back(std::move(*e));
        break;
      }
      case 3: {
        stripe_points_t m;
        decoded = m.decode(bytes, 0, n) == n;
        if (decoded) events.push_back(event_of(m));
        break;
      }
      case 4: {
        stripe_profile_t m;
        decoded = m.decode(bytes, 0, n) == n;
        if (decoded) events.push_back(event_of(m));
        break;
      }
      case 5: {
        stripe_cloud_t m;
        decoded = m.decode(bytes, 0, n) == n;
        if (decoded) events.push_back(event_of(m));
        break;
      }
      default:
        break;  // the tick
    }
    if (!decoded) continue;  // the bus counts a decode error
    std::vector<PlanEvent> batch;
    batch.swap(events);
    task.run(static_cast<double>(now_ms) * 1e-3, batch, arm_q, arm_moving);
    if (task.finished() && task.exit_code() != 0 && task.sequencer() != nullptr &&
        task.sequencer()->state() == ScanState::kFailed && task.sequencer()->reason().empty())
      fuzz::fail("a scan failed without a reason");
  }
  return 0;
}
