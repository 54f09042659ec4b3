#include "procs/shepherd/worldmodel/worldmodel_messages.h"

namespace ephor::worldmodel {

namespace {

int8_t to_state(ObjectState s) {
  switch (s) {
    case ObjectState::kVisible:
      return shepherd_object_t::STATE_VISIBLE;
    case ObjectState::kObscured:
      return shepherd_object_t::STATE_OBSCURED;
    case ObjectState::kDead:
      return shepherd_object_t::STATE_DEAD;
  }
  return shepherd_object_t::STATE_DEAD;
}

}  // namespace

bool blobs_consistent(const shepherd_blobs_t& msg) {
  return msg.num_blobs == static_cast<int32_t>(msg.blobs.size());
}

BlobFrame frame_of(const shepherd_blobs_t& msg) {
  BlobFrame frame;
  frame.utime_us = msg.utime;
  frame.frame_index = msg.frame_index;
  frame.blobs.reserve(msg.blobs.size());
  for (const auto& b : msg.blobs)
    frame.blobs.push_back({{static_cast<double>(b.u), static_cast<double>(b.v)}, b.area});
  return frame;
}

shepherd_objects_t objects_message_of(const WorldModel& wm, int64_t frame_index) {
  shepherd_objects_t msg;
  msg.utime = wm.last_utime_us();
  msg.frame_index = frame_index;
  for (const auto& o : wm.objects()) {
    shepherd_object_t m;
    m.id = o.id;
    m.state = to_state(o.state);
    m.u = static_cast<float>(o.position_px.x());
    m.v = static_cast<float>(o.position_px.y());
    m.x_mm = static_cast<float>(o.position_mm.x());
    m.y_mm = static_cast<float>(o.position_mm.y());
    m.vu_px_s = static_cast<float>(o.velocity_px_s.x());
    m.vv_px_s = static_cast<float>(o.velocity_px_s.y());
    m.vx_mm_s = static_cast<float>(o.velocity_mm_s.x());
    m.vy_mm_s = static_cast<float>(o.velocity_mm_s.y());
    m.since_seen_s = static_cast<float>(o.since_seen_s);
    m.area = o.area_px;
    m.vu_raw_px_s = static_cast<float>(o.velocity_raw_px_s.x());
    m.vv_raw_px_s = static_cast<float>(o.velocity_raw_px_s.y());
    m.vu_first_px_s = static_cast<float>(o.velocity_first_px_s.x());
    m.vv_first_px_s = static_cast<float>(o.velocity_first_px_s.y());
    msg.objects.push_back(m);
  }
  msg.num_objects = static_cast<int32_t>(msg.objects.size());
  return msg;
}

}  // namespace ephor::worldmodel
