// Fuzz target (issue 18): ephor-stripe-planner on any stream of what it
// subscribes to (ARM_STATE, MOTION_DONE, STRIPE_IMAGE, STRIPE_POINTS,
// STRIPE_PROFILE, STRIPE_CLOUD) with a clock: each message decoded the way
// the bus does (a message that does not decode to its full size is
// dropped), taken by its handler (arm_joints_of(): non-finite joints
// ignored; event_of(): an image only when the requester is "planner"), and
// the plan task run after each at the message's time as main.cc runs it: a
// scan planned from where the arm is (plan_raster() with the process's
// defaults, deploy/stripe/workcell.pbtxt and the drawing's calibration), each
// event through apply_event() into the ScanSequencer, its tick, the scan's
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
#include <vector>

#include "common/arm/arm_workcell.h"
#include "common/config/repo_paths.h"
#include "common/fuzz/fuzz_input.h"
#include "common/geometry/workcell_file.h"
#include "common/stripe/calibration_file.h"
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
// region and start joints (bit for bit).
std::optional<RasterPlan> plan_from(const RasterSpec& spec, bool small, const arm::Joints& q) {
  static std::map<std::vector<double>, std::optional<RasterPlan>> cache;
  std::vector<double> key(q.data(), q.data() + 6);
  key.push_back(small ? 1.0 : 0.0);
  if (const auto it = cache.find(key); it != cache.end()) return it->second;
  std::optional<RasterPlan> plan;
  try {
    plan = plan_raster(spec, setup().workcell, setup().calibration.arm_model(),
                       setup().calibration.sensor, q);
  } catch (const PlanError&) {
    // main.cc: logged, exit 1.
  }
  if (cache.size() > 4096) cache.clear();
  cache.emplace(key, plan);
  return plan;
}

template <typename M>
void check_encodes(const M& m, const char* what) {
  const int size = m.getEncodedSize();
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  if (m.encode(bytes.data(), 0, size) != size) fuzz::fail(std::string(what) + " does not encode");
}

// The process's state (main.cc's plan task and handlers).
struct Planner {
  RasterSpec spec;
  bool small = false;
  int scans = 1;
  double pause_s = 3.0, speed_mm_s = 0.0;

  std::optional<arm::Joints> arm_q;
  bool arm_moving = false;
  std::vector<PlanEvent> events;
  bool finished = false;
  std::optional<ScanSequencer> seq;
  RasterPlan plan;
  int64_t scan_id = 0, next_goal = kStartWallUs, next_request = kStartWallUs;
  int scans_done = 0;
  double last_status_s = 0.0, pause_until_s = 0.0;
  ScanCpu cpu;
  CloudEvent last_cloud{};
  // For the checks: every goal id sent, the request ids asked.
  std::set<int64_t> goal_ids;
  int64_t last_request = 0;

  void publish_scan(double t) {
    stripe_scan_t m = scan_message_of(*seq, spec, scan_id, t);
    m.utime = kStartWallUs;
    if (m.stripes_planned != static_cast<int>(plan.goals.size()) || m.stripes_captured < 0 ||
        m.stripes_captured > m.stripes_planned || m.stripes_skipped < 0 ||
        m.stripes_skipped > m.stripes_planned)
      fuzz::fail("STRIPE_SCAN's counts outside the plan");
    if (!std::isfinite(m.elapsed_s) || !std::isfinite(m.stripes_per_s) ||
        !(m.motion_s >= 0.0 && std::isfinite(m.motion_s)) || m.cloud_points < 0)
      fuzz::fail("STRIPE_SCAN's times or rates not finite");
    check_encodes(m, "STRIPE_SCAN");
    last_status_s = t;
  }

  void act(const SequencerActions& a, double t) {
    if (a.goal) {
      const GoalAction& g = *a.goal;
      if (g.stripe < 0 || g.stripe >= static_cast<int>(plan.goals.size()))
        fuzz::fail("a goal for a stripe not planned");
      if (!g.q.allFinite()) fuzz::fail("a goal that is not finite");
      if (!setup().limits.within(g.q)) fuzz::fail("a goal outside the joint limits");
      if (g.q != plan.goals[static_cast<size_t>(g.stripe)])
        fuzz::fail("a goal that is not its stripe's planned one");
      if (!goal_ids.insert(g.goal_id).second) fuzz::fail("a goal id sent twice");
      arm_goal_t m = goal_message_of(g, speed_mm_s);
      m.utime = kStartWallUs;
      if (m.kind != arm_goal_t::KIND_JOINTS || !(m.max_speed_mm_s >= 0.0f))
        fuzz::fail("a goal message of the wrong kind or speed");
      check_encodes(m, "ARM_GOAL");
    }
    if (a.capture) {
      const CaptureAction& c = *a.capture;
      if (c.stripe < -1 || c.stripe >= static_cast<int>(plan.goals.size()))
        fuzz::fail("a capture for a stripe not planned");
      if (c.request_id < last_request) fuzz::fail("a capture's request id went back");
      last_request = c.request_id;
      stripe_capture_t m = capture_message_of(c, scan_id);
      m.utime = kStartWallUs;
      if ((c.stripe < 0) != (m.scan_id == 0)) fuzz::fail("a capture in the wrong scan");
      check_encodes(m, "STRIPE_CAPTURE");
    }
    if (a.changed) publish_scan(t);
  }

  bool new_scan(double t) {
    const std::optional<RasterPlan> p = plan_from(spec, small, *arm_q);
    if (!p) return false;
    plan = *p;
    scan_id = kStartWallUs + static_cast<int64_t>(t * 1e6);
    seq.emplace(plan.goals, next_goal, next_request);
    cpu = ScanCpu{};
    last_cloud = CloudEvent{};
    act(seq->start(t), t);
    publish_scan(t);
    return true;
  }

  void job(double t) {
    std::vector<PlanEvent> batch;
    batch.swap(events);
    const std::optional<arm::Joints> q = arm_q;
    const bool moving = arm_moving;
    if (finished) return;
    if (!seq) {
      if (!q) return;
      if (!new_scan(t)) {
        finished = true;
        return;
      }
    }
    for (const PlanEvent& e : batch)
      apply_event(*seq, scan_id, e, t, cpu, &last_cloud,
                  [&](const SequencerActions& a) { act(a, t); });
    if (moving) seq->on_arm_moving(t);
    act(seq->tick(t), t);
    if (t - last_status_s >= 1.0) publish_scan(t);
    if (seq->finished() && pause_until_s == 0.0) {
      next_goal = seq->next_goal_id();
      next_request = seq->next_request_id();
      ++scans_done;
      if (seq->state() == ScanState::kFailed) {
        if (seq->reason().empty()) fuzz::fail("a scan failed without a reason");
        finished = true;
      } else if (scans > 0 && scans_done >= scans) {
        finished = true;
      } else {
        pause_until_s = t + pause_s;
      }
    }
    if (pause_until_s > 0.0 && t >= pause_until_s && q) {
      pause_until_s = 0.0;
      arm_q = q;
      if (!new_scan(t)) finished = true;
    }
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  Planner p;
  // main.cc's defaults.
  parse_region("-200,-200,200,200", p.spec);
  p.spec.pass_length_mm = 60.0;
  p.small = (data[0] & 1) != 0;
  if (p.small) parse_region("-20,-20,20,20", p.spec);
  if ((data[0] & 2) != 0) p.scans = 0;
  if ((data[0] & 4) != 0) p.speed_mm_s = 100.0;
  int64_t now_ms = 1'000'000;  // the process's monotonic clock
  size_t at = 1;
  for (int k = 0; k < 256 && at + 5 <= size && !p.finished; ++k) {
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
            p.arm_q = *q;
            p.arm_moving = m.moving;
          }
        }
        break;
      }
      case 1: {
        motion_done_t m;
        decoded = m.decode(bytes, 0, n) == n;
        if (decoded) p.events.push_back(event_of(m));
        break;
      }
      case 2: {
        stripe_image_t m;
        decoded = m.decode(bytes, 0, n) == n;
        if (decoded)
          if (auto e = event_of(m, "planner")) p.events.push_back(std::move(*e));
        break;
      }
      case 3: {
        stripe_points_t m;
        decoded = m.decode(bytes, 0, n) == n;
        if (decoded) p.events.push_back(event_of(m));
        break;
      }
      case 4: {
        stripe_profile_t m;
        decoded = m.decode(bytes, 0, n) == n;
        if (decoded) p.events.push_back(event_of(m));
        break;
      }
      case 5: {
        stripe_cloud_t m;
        decoded = m.decode(bytes, 0, n) == n;
        if (decoded) p.events.push_back(event_of(m));
        break;
      }
      default:
        break;  // the tick
    }
    if (!decoded) continue;  // the bus counts a decode error
    p.job(static_cast<double>(now_ms) * 1e-3);
  }
  return 0;
}
