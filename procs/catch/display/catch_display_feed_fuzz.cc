// Fuzz target (issue 18): ephor-catch-display's handlers on any stream of
// the channels it listens to (CAMERA through the frame hook,
// CATCH_BOARD_POSE, CATCH_SURVEY, CATCH_BALL, CATCH_WORLD, CATCH_TRUTH,
// ARM_STATE; ARM_GOAL has no handler): each message decoded as the bus does
// (one that does not decode to its full size is dropped) and fed through
// CatchDisplayFeed as main.cc feeds it, on a wall clock that moves by
// 0-262 ms a message, with deploy/catch's board and camera (the defaults of
// BoardSpec, 560 px focal length). Now and then, and at the end, GET
// /api/state's system part is built and written as json_text, as the
// DisplayServer serves it: it must be built and written without an
// exception, read back as JSON, and every number in it finite (the page
// draws numbers; nlohmann would write NaN and infinities as null).
//
// Input: a FuzzMessageStream (common/fuzz/fuzz_input.h) of up to 256
// messages of up to 4096 bytes, channels in the order above. Seeds:
// fuzz_corpus/catch_display (a frame, the board pose, the survey, a ball
// rolling down with the world model's prediction, the truth and the arm;
// a board pose that is not valid and a survey that is refused).
#include <cstddef>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "common/fuzz/fuzz_input.h"
#include "common/fuzz/json_checks.h"
#include "common/log/json_text.h"
#include "procs/catch/display/catch_display_feed.h"

namespace {

using namespace ephor;

void check(const catch_display::CatchDisplayFeed& feed, int64_t now_us) {
  const nlohmann::json j = feed.state(now_us);
  if (const std::string at = fuzz::first_non_finite(j); !at.empty())
    fuzz::fail("a number that is not finite in the state at " + at + ": " + json_text(j));
  const std::string text = json_text(j);
  if (!nlohmann::json::accept(text)) fuzz::fail("state text that is not JSON: " + text);
}

catching::CameraIntrinsics deploy_camera() {
  catching::CameraIntrinsics c;  // deploy/catch/camera.pbtxt
  c.fx = c.fy = 560.0;
  return c;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  catch_display::CatchDisplayFeed feed(catching::BoardSpec{}, deploy_camera());
  int64_t now_us = 1'700'000'000'000'000;
  check(feed, now_us);
  fuzz::FuzzMessageStream stream(data, size, 7);
  fuzz::FuzzMessage msg;
  for (int k = 0; stream.next(msg); ++k) {
    now_us += msg.step_us;
    switch (msg.channel) {
      case 0: {
        camera_frame_t m;
        if (msg.decode(m)) feed.on_frame(m, now_us);
        break;
      }
      case 1: {
        catch_board_pose_t m;
        if (msg.decode(m)) feed.on_board_pose(m, now_us);
        break;
      }
      case 2: {
        catch_survey_t m;
        if (msg.decode(m)) feed.on_survey(m, now_us);
        break;
      }
      case 3: {
        catch_ball_t m;
        if (msg.decode(m)) feed.on_ball(m, now_us);
        break;
      }
      case 4: {
        catch_world_t m;
        if (msg.decode(m)) feed.on_world(m, now_us);
        break;
      }
      case 5: {
        catch_truth_t m;
        if (msg.decode(m)) feed.on_truth(m, now_us);
        break;
      }
      default: {
        arm_state_t m;
        if (msg.decode(m)) feed.on_arm_state(m, now_us);
        break;
      }
    }
    if (k % 8 == 7) check(feed, now_us);
  }
  check(feed, now_us);
  return 0;
}
