// Fuzz target (issue 18): ephor-catch-prim's plan task on any stream of
// CATCH_WORLD and ARM_STATE messages: each decoded the way the bus does (a
// message that does not decode to its full size is dropped), the cup taken
// by cup_of() (non-finite refused), each world by prediction_of() (a
// non-finite catch point or sigma refused), CatchPlanner::step() with the
// process's defaults (PrimTuning, the board and placement of the defaults)
// on a clock that moves by 0-262 ms a message, and every goal it sends as
// goal_message_of() publishes it. A goal must be finite and inside the
// planner's reachable box: it is where the arm is sent.
//
// Input: up to 256 messages, each a byte naming the channel (even: CATCH_WORLD,
// odd: ARM_STATE), two bytes of clock step (us, little-endian, x 4) and a
// 1-byte length, then that many bytes. Seeds: fuzz_corpus/catch_prim_world
// (a cup at the ready point and a ball's predictions closing in).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "common/catch/board_model.h"
#include "common/catch/prim/catch_planner.h"
#include "common/fuzz/fuzz_input.h"
#include "procs/catch/prim/prim_messages.h"

namespace {

using namespace ephor;
using namespace ephor::catching;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const BoardSpec board;
  const BoardPlacement placement;
  const CatchPlannerParams params =
      PrimTuning{}.apply(CatchPlannerParams::for_board(board, placement));
  CatchPlanner planner(board, placement, params);
  std::optional<Eigen::Vector3d> cup;
  int64_t now_us = 1'700'000'000'000'000;
  size_t at = 0;
  for (int k = 0; k < 256 && at + 4 <= size; ++k) {
    const bool world_message = (data[at] & 1) == 0;
    now_us += 4 * static_cast<int64_t>(data[at + 1] | (data[at + 2] << 8));
    const size_t len = data[at + 3];
    at += 4;
    if (len > size - at) break;
    const int n = static_cast<int>(len);
    const uint8_t* bytes = data + at;
    at += len;
    if (!world_message) {
      arm_state_t state;
      if (state.decode(bytes, 0, n) != n) continue;
      if (const auto p = cup_of(state)) cup = p;
      continue;
    }
    catch_world_t world;
    if (world.decode(bytes, 0, n) != n) continue;
    if (!cup) continue;  // the plan task waits for the arm's first state
    bool bad = false;
    const std::optional<CatchPrediction> prediction = prediction_of(world, &bad);
    if (bad && prediction) fuzz::fail("a non-finite prediction was chased");
    const CatchGoal g = planner.step(now_us, prediction, *cup);
    if (!g.send) continue;
    if (!g.point_w_mm.allFinite()) fuzz::fail("a goal that is not finite");
    for (int i = 0; i < 3; ++i)
      if (g.point_w_mm[i] < params.reach_min_w_mm[i] - 1e-6 ||
          g.point_w_mm[i] > params.reach_max_w_mm[i] + 1e-6)
        fuzz::fail("a goal outside the reachable box");
    const arm_goal_t m = goal_message_of(g, world, now_us);
    const int out_size = m.getEncodedSize();
    std::vector<uint8_t> out(static_cast<size_t>(out_size));
    if (m.encode(out.data(), 0, out_size) != out_size) fuzz::fail("the goal does not encode");
  }
  return 0;
}
