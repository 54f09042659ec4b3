// Fuzz target (issue 18): ephor-catch-worldmodel's model task on any stream
// of CATCH_BALL messages: each decoded as catch_ball_t the way the bus does
// (a message that does not decode to its full size is dropped), its centroid
// taken by centroid_of() (non-finite refused), BallWorldModel::update() at the
// message's capture time (any: backwards, repeated, years apart), the frame
// published by world_message_of() and encoded. The model is the process's
// (the board, camera and placement of the defaults, with or without pegs,
// the exit's spread and the acquisition limit the manifest sets). A frame
// with a state must have a finite one, and a prediction a finite catch
// point: Prim aims the arm there.
//
// Input: one byte of settings (bit 0: pegs, bit 1: --spread-samples 8,
// bit 2: acquire only high on the board), then up to 256 messages, each a
// 1-byte length and that many bytes. Seeds: fuzz_corpus/catch_world_model
// (a ball rolling down the board, 60 frames).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/catch/board_model.h"
#include "common/catch/worldmodel/ball_world_model.h"
#include "common/catch/worldmodel/test_scene.h"
#include "common/fuzz/fuzz_input.h"
#include "procs/catch/worldmodel/world_message.h"

namespace {

using namespace ephor;
using namespace ephor::catching;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const BoardSpec board;
  const BoardPlacement placement;
  const CameraIntrinsics intrinsics;
  BallWorldModelParams params;
  if ((data[0] & 2) != 0) params.spread.samples = 8;
  if ((data[0] & 4) != 0) params.acquire_max_y_mm = 150.0;  // as the process sets it
  BallWorldModel model(board, placement, intrinsics, testing::camera_looking_at_board(board),
                       params);
  if ((data[0] & 1) != 0) {
    std::vector<Eigen::Vector2d> pegs;
    for (int i = 0; i < 6; ++i)
      pegs.emplace_back(100.0 + 80.0 * i, 200.0 + 90.0 * (i % 3));  // within the board
    model.set_pegs(pegs, 10.0);
  }
  size_t at = 1;
  for (int k = 0; k < 256 && at < size; ++k) {
    const size_t len = data[at++];
    if (len > size - at) break;
    catch_ball_t ball;
    const int n = static_cast<int>(len);
    const bool whole = ball.decode(data + at, 0, n) == n;
    at += len;
    if (!whole) continue;  // the bus counts a decode error
    bool bad = false;
    const auto centroid = centroid_of(ball, &bad);
    if (bad && centroid) fuzz::fail("a non-finite centroid was used");
    const BallFrame& f = model.update(ball.utime, centroid);
    const catch_world_t m = world_message_of(f, ball);
    if (f.has_state && !(f.position_b_mm.allFinite() && f.velocity_b_mm_s.allFinite()))
      fuzz::fail("a state that is not finite");
    if (m.has_prediction &&
        !(std::isfinite(m.catch_point_w_mm[0]) && std::isfinite(m.catch_point_w_mm[1]) &&
          std::isfinite(m.catch_point_w_mm[2])))
      fuzz::fail("a prediction whose catch point is not finite");
    const int bytes = m.getEncodedSize();
    std::vector<uint8_t> out(static_cast<size_t>(bytes));
    if (m.encode(out.data(), 0, bytes) != bytes) fuzz::fail("the frame does not encode");
  }
  return 0;
}
