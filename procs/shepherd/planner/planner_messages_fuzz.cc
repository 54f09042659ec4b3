// Fuzz target (issue 18): ephor-planner's handlers and plan task on any
// interleaved stream of OBJECTS, ARM_STATE and MOTION_DONE messages, each
// decoded the way the bus does (a message that does not decode to its full
// size is dropped), on a monotonic clock that moves by 0-65.5 s a message.
// As in main.cc: OBJECTS and ARM_STATE are kept as the newest of each, a
// MOTION_DONE is queued with the capture utime of the newest OBJECTS, and
// every OBJECTS runs the job: the queued MOTION_DONEs to the planner
// (planner_goal_id()), the stale-frame rule, the work cell agreement
// (arm_plane()), the arm from arm_model_of(), the sheep from sheep_of(),
// Planner::plan() (make_planner() with the default PlannerConfig and work
// cell, the arm assumed parked until ARM_STATE comes), the goal as
// goal_message_of() and the status as status_message_of() publish them
// through the simulator's calibration (FieldCalibration::from_camera, what
// deploy/calibration/sim.pbtxt holds). A goal must be finite (in F and in
// the image) and where the planner's rules put the arm: raised in place
// where ARM_STATE says the tool is, or outside the column's keep-out
// (tool_keepout_mm) and then, serving a sheep or in the object plane,
// inside the field by field_margin_mm (FieldRules::usable_point), or,
// parking from a tool inside the field, inside the field. Both messages
// must encode.
//
// Input: one byte of settings (value % 3: --planner single, multi,
// lookahead; bits 2-3: --arm-speed-mm-s 300, 30, 1000, 5000), then up to
// 256 messages, each a byte naming the channel (value % 4: 0 OBJECTS,
// 1 ARM_STATE, 2 MOTION_DONE, 3 MOTION_DONE whose goal_id is replaced by
// the newest goal's published, as the arm answers), two bytes of clock step
// (ms, little-endian), a 2-byte length (little-endian) and that many bytes.
// Seeds: fuzz_corpus/shepherd_planner: for each planner a save cycle
// recorded in a closed loop (sheep walking out at 30 mm/s seen every
// 250-300 ms, an arm that reaches each goal, reports it on ARM_STATE and
// answers MOTION_DONE, the lowered tool turning the sheep: move, lower,
// raise, park legs), and a stream with an arm resting on another work
// cell's plane, motion_dones for goals never sent, a stale frame and
// objects with NaN, huge or unknown fields; goal_id_overflow, a MOTION_DONE
// naming goal INT64_MIN (it overflowed planner_goal_id()).
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/calibration/field_calibration.h"
#include "common/fuzz/fuzz_input.h"
#include "common/geometry/workcell.h"
#include "ephor/motion_done_t.hpp"
#include "ephor/shepherd_objects_t.hpp"
#include "procs/shepherd/planner/planner.h"
#include "procs/shepherd/planner/planner_messages.h"
#include "procs/shepherd/planner/workcell_agreement.h"

namespace {

using namespace ephor;
using namespace ephor::planner;

// The goal's place against the planner's rules (see the header comment).
void check_goal(const Goal& g, const Scene& scene, const PlannerConfig& config) {
  if (!(std::isfinite(g.x_mm) && std::isfinite(g.y_mm) && std::isfinite(g.theta_rad)))
    fuzz::fail("a goal that is not finite");
  const geometry::Workcell& cell = config.workcell;
  const bool in_place =
      g.plane == Plane::kElevation && g.x_mm == scene.arm.x_mm && g.y_mm == scene.arm.y_mm;
  if (in_place) return;          // raising the tool where it is
  constexpr double kTol = 1e-6;  // mm
  if (std::hypot(g.x_mm - cell.base_x_mm, g.y_mm - cell.base_y_mm) < config.tool_keepout_mm - kTol)
    fuzz::fail("a goal inside the column's keep-out");
  const auto inside = [&](double margin_mm) {
    return g.x_mm >= margin_mm - kTol && g.x_mm <= cell.field_length_mm - margin_mm + kTol &&
           g.y_mm >= margin_mm - kTol && g.y_mm <= cell.field_width_mm - margin_mm + kTol;
  };
  if (g.target >= 0 || g.plane == Plane::kObject) {
    if (!inside(config.field_margin_mm)) fuzz::fail("a goal serving a sheep off the field");
  } else if (cell.inside_field(scene.arm.x_mm, scene.arm.y_mm) && !inside(0.0)) {
    fuzz::fail("a parking goal off the field from a tool on it");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const std::vector<std::string> kinds = planner_kinds();
  const std::string kind = kinds[data[0] % kinds.size()];
  const double speeds_mm_s[4] = {300.0, 30.0, 1000.0, 5000.0};
  PlannerConfig config;  // the default work cell, as without --workcell
  ArmModel arm_model;
  arm_model.speed_mm_s = speeds_mm_s[(data[0] >> 2) & 3];
  arm_model.x_mm = config.park_x_mm;  // until ARM_STATE arrives, as main.cc
  arm_model.y_mm = config.park_y_mm;
  const calibration::FieldCalibration calibration =
      calibration::FieldCalibration::from_camera({}, config.workcell);
  const std::unique_ptr<Planner> planner = make_planner(kind, config);
  WorkcellAgreement agreement(config.workcell);
  const int64_t goal_id_offset = 1'700'000'000'000'000;  // the process's wall clock at start, us

  struct Done {
    int64_t goal_id;
    bool ok;
    int64_t objects_utime;
  };
  std::vector<Done> dones;
  std::optional<shepherd_objects_t> objects;
  std::optional<arm_state_t> arm;
  int64_t stale_until_utime = INT64_MIN;
  std::optional<int64_t> newest_goal_id;
  int64_t now_ns = 1'000'000'000'000;  // monotonic, ns
  size_t at = 1;
  for (int k = 0; k < 256 && at + 5 <= size; ++k) {
    const int channel = data[at] % 4;
    now_ns += 1'000'000 * static_cast<int64_t>(data[at + 1] | (data[at + 2] << 8));
    const size_t len = data[at + 3] | (data[at + 4] << 8);
    at += 5;
    if (len > size - at) break;
    const int n = static_cast<int>(len);
    const uint8_t* bytes = data + at;
    at += len;
    if (channel == 1) {
      arm_state_t state;
      if (state.decode(bytes, 0, n) == n) arm = state;
      continue;
    }
    if (channel == 2 || channel == 3) {
      motion_done_t done;
      if (done.decode(bytes, 0, n) != n) continue;
      if (channel == 3 && newest_goal_id) done.goal_id = *newest_goal_id;
      dones.push_back({done.goal_id, done.status == motion_done_t::STATUS_DONE,
                       objects ? objects->utime : INT64_MIN});
      continue;
    }
    shepherd_objects_t msg;
    if (msg.decode(bytes, 0, n) != n) continue;
    objects = msg;

    // The plan job, as PlanJob::operator() runs it.
    for (const Done& d : dones) {
      (void)planner->on_motion_done(planner_goal_id(d.goal_id, goal_id_offset), d.ok);
      stale_until_utime = std::max(stale_until_utime, d.objects_utime);
    }
    dones.clear();
    if (objects->utime <= stale_until_utime) continue;
    Scene scene;
    scene.now_s = static_cast<double>(now_ns) * 1e-9;
    scene.arm = arm_model;
    if (arm) {
      (void)agreement.update(arm_plane(*arm), static_cast<double>(arm->z_mm));
      if (!agreement.agrees()) {
        PlannerStatus st = planner->status();
        st.phase = "workcell mismatch";
        fuzz::check_encodes(status_message_of(st, planner->kind(), calibration, goal_id_offset,
                                              objects->utime, 0.0f),
                            "PLANNER_STATUS");
        continue;
      }
      if (const auto model = arm_model_of(*arm, arm_model, config.workcell)) scene.arm = *model;
    }
    for (const shepherd_object_t& o : objects->objects)
      if (const auto s = sheep_of(o)) scene.sheep.push_back(*s);
    const std::optional<Goal> goal = planner->plan(scene);
    const PlannerStatus st = planner->status();
    if (goal) {
      check_goal(*goal, scene, config);
      const arm_goal_t m = goal_message_of(*goal, calibration, goal_id_offset, objects->utime);
      if (!(std::isfinite(m.u) && std::isfinite(m.v) && std::isfinite(m.theta_rad)))
        fuzz::fail("a goal whose image point or orientation is not finite");
      fuzz::check_encodes(m, "ARM_GOAL");
      newest_goal_id = m.goal_id;
    }
    fuzz::check_encodes(
        status_message_of(st, planner->kind(), calibration, goal_id_offset, objects->utime, 1.0f),
        "PLANNER_STATUS");
  }
  return 0;
}
