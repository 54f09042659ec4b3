// Fuzz target (issue 18): ephor-worldmodel's associate task on any stream of
// BLOBS messages: each decoded as shepherd_blobs_t the way the bus does (a
// message that does not decode to its full size is dropped), checked by
// blobs_consistent(), taken by frame_of() into WorldModel::process() at the
// message's capture utime (any: backwards, repeated, years apart; duplicate
// and out-of-order frames publish nothing, as in the task), and the OBJECTS
// message objects_message_of() builds, encoded; the model's events taken as
// the task logs them. The model is the process's: the simulator's
// calibration (FieldCalibration::from_camera of the default camera and work
// cell, what deploy/calibration/sim.pbtxt holds), the default work cell and
// the flags' defaults (mark height 52 mm, mark diameter 42 mm). Every
// published object must be finite (position, velocities, time hidden: the
// planner aims the arm by them) and of a known state, its id unique within
// the message, and the message must encode.
//
// Input: one byte of settings (bit 0: --mark-diameter-mm 0, bit 1:
// --max-obscured-s 1), then up to 256 messages, each a 2-byte length
// (little-endian) and that many bytes. Seeds: fuzz_corpus/shepherd_world_model
// (three sheep walking across the field for 60 frames, one of them hidden
// for a while; a frame repeated and one out of order; blobs with NaN centres
// and zero areas; utimes_far_apart, frames at -9.2e18 us and 1.7e15 us,
// which overflowed WorldModel's time differences).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <set>
#include <vector>

#include "common/calibration/field_calibration.h"
#include "common/fuzz/fuzz_input.h"
#include "common/shepherd/worldmodel/world_model.h"
#include "procs/shepherd/worldmodel/worldmodel_messages.h"

namespace {

using namespace ephor;
using namespace ephor::worldmodel;

bool finite_object(const shepherd_object_t& o) {
  for (const float x :
       {o.u, o.v, o.x_mm, o.y_mm, o.vu_px_s, o.vv_px_s, o.vx_mm_s, o.vy_mm_s, o.since_seen_s,
        o.vu_raw_px_s, o.vv_raw_px_s, o.vu_first_px_s, o.vv_first_px_s})
    if (!std::isfinite(x)) return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  WorldModelConfig config;
  config.mark_diameter_mm = 42.0;  // as main.cc sets it
  if ((data[0] & 1) != 0) config.mark_diameter_mm = 0.0;
  if ((data[0] & 2) != 0) config.max_obscured_s = 1.0;
  WorldModel wm(calibration::FieldCalibration::from_camera({}, {}), config);
  size_t at = 1;
  for (int k = 0; k < 256 && at + 2 <= size; ++k) {
    const size_t len = data[at] | (data[at + 1] << 8);
    at += 2;
    if (len > size - at) break;
    shepherd_blobs_t blobs;
    const int n = static_cast<int>(len);
    const bool whole = blobs.decode(data + at, 0, n) == n;
    at += len;
    if (!whole) continue;  // the bus counts a decode error
    if (!blobs_consistent(blobs)) fuzz::fail("a decoded BLOBS whose num_blobs is not its size");
    const WorldModel::FrameResult result = wm.process(frame_of(blobs));
    if (result != WorldModel::FrameResult::kProcessed) continue;  // warned, nothing published
    const shepherd_objects_t out = objects_message_of(wm, blobs.frame_index);
    (void)wm.take_events();
    if (out.num_objects != static_cast<int32_t>(out.objects.size()))
      fuzz::fail("num_objects is not the number of objects");
    std::set<int32_t> ids;
    for (const shepherd_object_t& o : out.objects) {
      if (!finite_object(o)) fuzz::fail("an object that is not finite");
      if (o.state != shepherd_object_t::STATE_VISIBLE &&
          o.state != shepherd_object_t::STATE_OBSCURED && o.state != shepherd_object_t::STATE_DEAD)
        fuzz::fail("an object of unknown state");
      if (!ids.insert(o.id).second) fuzz::fail("an id twice in one message");
    }
    const int bytes = out.getEncodedSize();
    std::vector<uint8_t> buffer(static_cast<size_t>(bytes));
    if (out.encode(buffer.data(), 0, bytes) != bytes) fuzz::fail("OBJECTS does not encode");
  }
  return 0;
}
