#include "procs/stripe/planner/planner_messages.h"

#include "common/stripe/stripe_messages.h"

namespace ephor::stripe {

std::optional<PlanEvent> event_of(const stripe_image_t& m, const std::string& name) {
  if (m.requester != name) return std::nullopt;
  return ImageEvent{m.request_id, m.image_index};
}

PlanEvent event_of(const stripe_points_t& m) {
  return PointsEvent{m.image_index, m.scan_id, m.stripe_index, m.scan_stripes, m.cpu_us};
}

PlanEvent event_of(const stripe_profile_t& m) { return ProfileEvent{m.scan_id, m.cpu_us}; }

PlanEvent event_of(const motion_done_t& m) { return DoneEvent{m.goal_id, m.status, m.reason}; }

PlanEvent event_of(const stripe_cloud_t& m) {
  return CloudEvent{m.scan_id, m.points, m.stripes_missing, m.path, m.error};
}

std::optional<arm::Joints> arm_joints_of(const arm_state_t& m) {
  const arm::Joints q = joints_of(m.q);
  if (!q.allFinite()) return std::nullopt;
  return q;
}

void apply_event(ScanSequencer& seq, int64_t scan_id, const PlanEvent& event, double now_s,
                 ScanCpu& cpu, CloudEvent* last_cloud,
                 const std::function<void(const SequencerActions&)>& act) {
  if (const auto* i = std::get_if<ImageEvent>(&event)) {
    act(seq.on_image(i->request_id, i->image_index, now_s));
  } else if (const auto* p = std::get_if<PointsEvent>(&event)) {
    if (p->scan_id == scan_id && p->scan_id != 0) {
      cpu.range_cpu_us += static_cast<double>(p->cpu_us);
      ++cpu.range_n;
      act(seq.on_ranged(p->stripe_index, p->scan_stripes, now_s));
    }
    act(seq.on_points(p->image_index, now_s));
  } else if (const auto* f = std::get_if<ProfileEvent>(&event)) {
    if (f->scan_id == scan_id && f->scan_id != 0) {
      cpu.extract_cpu_us += static_cast<double>(f->cpu_us);
      ++cpu.extract_n;
    }
  } else if (const auto* d = std::get_if<DoneEvent>(&event)) {
    act(seq.on_motion_done(d->goal_id, d->status, d->reason, now_s));
  } else if (const auto* c = std::get_if<CloudEvent>(&event)) {
    if (c->scan_id != scan_id) return;
    if (last_cloud) *last_cloud = *c;
    act(seq.on_cloud(c->points, now_s));
  }
}

arm_goal_t goal_message_of(const GoalAction& goal, double speed_mm_s) {
  arm_goal_t g{};
  g.goal_id = goal.goal_id;
  g.kind = arm_goal_t::KIND_JOINTS;
  set_joints(goal.q, g.joints_rad);
  g.max_speed_mm_s = static_cast<float>(speed_mm_s);
  g.target_object = -1;
  return g;
}

stripe_capture_t capture_message_of(const CaptureAction& capture, int64_t scan_id) {
  stripe_capture_t c{};
  c.request_id = capture.request_id;
  c.scan_id = capture.stripe >= 0 ? scan_id : 0;
  c.stripe_index = capture.stripe;
  c.mode = stripe_capture_t::MODE_STRIPE;
  return c;
}

stripe_scan_t scan_message_of(const ScanSequencer& seq, const RasterSpec& spec, int64_t scan_id,
                              double now_s) {
  stripe_scan_t m{};
  m.scan_id = scan_id;
  switch (seq.state()) {
    case ScanState::kWaiting:
      m.state = stripe_scan_t::STATE_WAITING;
      break;
    case ScanState::kRunning:
      m.state = stripe_scan_t::STATE_RUNNING;
      break;
    case ScanState::kCaptured:
      m.state = stripe_scan_t::STATE_CAPTURED;
      break;
    case ScanState::kDone:
      m.state = stripe_scan_t::STATE_DONE;
      break;
    case ScanState::kFailed:
      m.state = stripe_scan_t::STATE_FAILED;
      break;
  }
  m.reason = seq.reason();
  m.region_mm[0] = spec.x0_mm;
  m.region_mm[1] = spec.y0_mm;
  m.region_mm[2] = spec.x1_mm;
  m.region_mm[3] = spec.y1_mm;
  m.step_mm = spec.step_mm;
  m.height_mm = spec.height_mm;
  m.stripes_along_y = spec.stripes_along_y;
  m.stripes_planned = seq.planned();
  m.stripes_captured = seq.captured();
  m.stripes_skipped = seq.skipped();
  m.elapsed_s = seq.elapsed_s(now_s);
  m.stripes_per_s = seq.stripes_per_s();
  m.motion_s = seq.motion_s();
  m.cloud_points = seq.cloud_points();
  return m;
}

}  // namespace ephor::stripe
