#pragma once
// ephor-stripe-planner's messages in and out, as its handlers and plan task
// convert them (out of main.cc, so that the fuzz target
// planner_messages_fuzz.cc runs what the process runs): the messages it
// waits for as the plan task's events, each event given to the
// ScanSequencer, and the sequencer's answers as ARM_GOAL, STRIPE_CAPTURE
// and STRIPE_SCAN. Joints in rad, lengths in mm, times in s of the
// process's monotonic clock.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <variant>

#include "common/arm/puma560.h"
#include "common/stripe/scan_geometry.h"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/motion_done_t.hpp"
#include "ephor/stripe_capture_t.hpp"
#include "ephor/stripe_cloud_t.hpp"
#include "ephor/stripe_image_t.hpp"
#include "ephor/stripe_points_t.hpp"
#include "ephor/stripe_profile_t.hpp"
#include "ephor/stripe_scan_t.hpp"
#include "procs/stripe/planner/scan_sequencer.h"

namespace ephor::stripe {

// The plan task's events, what it keeps of each message.
struct ImageEvent {
  int64_t request_id, image_index;
};
struct PointsEvent {
  int64_t image_index, scan_id;
  int stripe_index, scan_stripes;
  float cpu_us;
};
struct ProfileEvent {
  int64_t scan_id;
  float cpu_us;
};
struct DoneEvent {
  int64_t goal_id;
  int status;
  std::string reason;
};
struct CloudEvent {
  int64_t scan_id, points;
  int stripes_missing;
  std::string path, error;
};
using PlanEvent = std::variant<ImageEvent, PointsEvent, ProfileEvent, DoneEvent, CloudEvent>;

// An image is the planner's event only when it asked for it (requester is
// its process name).
std::optional<PlanEvent> event_of(const stripe_image_t& m, const std::string& name);
PlanEvent event_of(const stripe_points_t& m);
PlanEvent event_of(const stripe_profile_t& m);
PlanEvent event_of(const motion_done_t& m);
PlanEvent event_of(const stripe_cloud_t& m);

// ARM_STATE's joint readings, or nullopt when one is not finite (ignored).
std::optional<arm::Joints> arm_joints_of(const arm_state_t& m);

// The scan's processing time reported by the stripe and range processes.
struct ScanCpu {
  double extract_cpu_us = 0.0, range_cpu_us = 0.0;
  int extract_n = 0, range_n = 0;
};

// One event given to the scan `scan_id`'s sequencer at now_s, each of its
// answers to `act` as it comes (points give two: on_ranged() for this scan's,
// then on_points(); a profile or another scan's cloud none). Points and
// profiles of this scan add to `cpu`; its cloud becomes *last_cloud.
void apply_event(ScanSequencer& seq, int64_t scan_id, const PlanEvent& event, double now_s,
                 ScanCpu& cpu, CloudEvent* last_cloud,
                 const std::function<void(const SequencerActions&)>& act);

// The joint goal (KIND_JOINTS) at the asked tool speed (--speed-mm-s, 0 =
// the arm's default). utime is the caller's to set.
arm_goal_t goal_message_of(const GoalAction& goal, double speed_mm_s);
// The capture of a stripe of scan `scan_id` (the probe's belongs to no
// scan). utime is the caller's to set.
stripe_capture_t capture_message_of(const CaptureAction& capture, int64_t scan_id);
// The scan's state and counts at now_s. utime is the caller's to set.
stripe_scan_t scan_message_of(const ScanSequencer& seq, const RasterSpec& spec, int64_t scan_id,
                              double now_s);

}  // namespace ephor::stripe
