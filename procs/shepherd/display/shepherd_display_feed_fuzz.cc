// Fuzz target (issue 18): ephor-display (the shepherding page) on any stream
// of the messages it hears: each decoded as the bus does (one that does not
// decode to its full size is dropped), kept as the channel's newest for the
// debug dump (as DisplayServer::subscribe does) and handed to
// ShepherdDisplayFeed as main.cc's handlers hand it, on a wall clock that
// moves by 0-262 ms a message; now and then, and at the end, the page's
// state (GET /api/state) and the debug dump's channels written as JSON text.
// Both must be written whatever the messages said (strings on the wire are
// any bytes), and the state, which the page draws, must carry only finite
// numbers.
//
// Input: a FuzzMessageStream (common/fuzz/fuzz_input.h) of up to 256
// messages of up to 4096 bytes; channels: CAMERA (its size only: the page's
// frame hook), BLOBS, VISION_CMD, OBJECTS, PLANNER_STATUS, PLANNER_CMD,
// ARM_STATE, GROUND_TRUTH, SIM_CMD, ARM_CMD. Seeds:
// fuzz_corpus/shepherd_display (two frames of a herd: blobs, objects,
// planner, arm, truth, a command, the controls).
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/calibration/field_calibration.h"
#include "common/config/repo_paths.h"
#include "common/display/newest_messages.h"
#include "common/fuzz/fuzz_input.h"
#include "common/fuzz/json_checks.h"
#include "common/geometry/workcell.h"
#include "common/lcm/channels.h"
#include "common/log/json_text.h"
#include "procs/shepherd/display/shepherd_display_feed.h"
#include "procs/shepherd/display/shepherd_lcm_json.h"

namespace {

using namespace ephor;
using namespace ephor::display;

// The page's overlay as ephor-display builds it by default: the simulator's
// calibration (deploy/calibration/sim.pbtxt), the default work cell.
OverlayGeometry sim_geometry() {
  const auto calibration = calibration::FieldCalibration::load(default_calibration_path());
  const geometry::Workcell cell;
  return OverlayGeometry(calibration.matrix_at_height(0.0), cell.field_length_mm,
                         cell.field_width_mm);
}

template <typename T, typename Feed>
void hear(NewestMessages& newest, const char* channel, const fuzz::FuzzMessage& msg, Feed feed) {
  T m;
  if (!msg.decode(m)) return;
  newest.put(channel, m);
  feed(m);
}

void check(const ShepherdDisplayFeed& feed, const NewestMessages& newest, int64_t now_us) {
  const nlohmann::json state = feed.state(now_us);
  if (const std::string at = fuzz::first_non_finite(state); !at.empty())
    fuzz::fail("a number that is not finite in the page's state at " + at);
  if (json_text(state).empty()) fuzz::fail("an empty state");
  if (json_text(newest.to_json()).empty()) fuzz::fail("an empty debug dump");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const OverlayGeometry geometry = sim_geometry();
  ShepherdDisplayFeed feed(geometry, DisplayOptions{}, 1);
  NewestMessages newest;
  int64_t now_us = 1'700'000'000'000'000;
  fuzz::FuzzMessageStream stream(data, size, 10);
  fuzz::FuzzMessage msg;
  for (int k = 0; stream.next(msg); ++k) {
    now_us += msg.step_us;
    const int64_t now = now_us;
    switch (msg.channel) {
      case 0: {
        camera_frame_t m;
        if (msg.decode(m)) feed.on_frame(m, now);
        break;
      }
      case 1:
        hear<shepherd_blobs_t>(newest, channels::kBlobs, msg,
                               [&](const auto& m) { feed.on_blobs(m, now); });
        break;
      case 2:
        hear<shepherd_vision_cmd_t>(newest, channels::kVisionCmd, msg,
                                    [&](const auto& m) { feed.on_vision_cmd(m); });
        break;
      case 3:
        hear<shepherd_objects_t>(newest, channels::kObjects, msg,
                                 [&](const auto& m) { feed.on_objects(m, now); });
        break;
      case 4:
        hear<shepherd_planner_status_t>(newest, channels::kPlannerStatus, msg,
                                        [&](const auto& m) { feed.on_planner_status(m, now); });
        break;
      case 5:
        hear<shepherd_planner_cmd_t>(newest, channels::kPlannerCmd, msg,
                                     [&](const auto& m) { feed.on_planner_cmd(m); });
        break;
      case 6:
        hear<arm_state_t>(newest, channels::kArmState, msg,
                          [&](const auto& m) { feed.on_arm_state(m, now); });
        break;
      case 7:
        hear<shepherd_ground_truth_t>(newest, channels::kGroundTruth, msg,
                                      [&](const auto& m) { feed.on_truth(m, now); });
        break;
      case 8:
        hear<shepherd_sim_cmd_t>(newest, channels::kSimCmd, msg,
                                 [&](const auto& m) { feed.on_sim_cmd(m); });
        break;
      default:
        hear<arm_cmd_t>(newest, channels::kArmCmd, msg, [&](const auto& m) { feed.on_arm_cmd(m); });
        break;
    }
    if (k % 16 == 15) check(feed, newest, now_us);
  }
  check(feed, newest, now_us);
  return 0;
}
