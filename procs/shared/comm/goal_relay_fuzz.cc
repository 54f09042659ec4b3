// Fuzz target (issue 18): ephor-comm's protocol (GoalRelay) driven by a
// sequence of events read off the fuzzer's bytes, as main.cc feeds it: goals
// from the planner (every field arbitrary: NaN, infinities, unknown kinds,
// trajectories of any length), acks from the arm (any seq and goal id, the
// four statuses main.cc accepts, any planned duration), the arm's progress,
// and steps with time moving forward by up to 2 s.
//
// Besides no crash, it checks what the protocol promises: a seq is sent
// first once and seqs increase, a retransmission repeats its seq's goal, and
// a goal the arm reported DONE is never sent again under a new seq while it
// is remembered (RelayOptions::finished_memory): the arm executes no goal
// twice. Seeds: fuzz_corpus/comm_goal_relay.
#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <utility>

#include "common/fuzz/fuzz_input.h"
#include "procs/shared/comm/goal_relay.h"

using ephor::comm::Ack;
using ephor::comm::AckStatus;
using ephor::comm::Goal;
using ephor::fuzz::FuzzBytes;

namespace {

Goal take_goal(FuzzBytes& in) {
  Goal g;
  g.goal_id = in.take_in(0, 7);  // few ids: duplicates and republished goals come up
  g.planned_utime = in.take_in(0, 3);
  g.kind = in.take<int8_t>();
  g.plane = in.take<int8_t>();
  g.u = in.take<float>();
  g.v = in.take<float>();
  g.theta_rad = in.take<float>();
  g.max_speed_mm_s = in.take<float>();
  g.target_object = in.take<int32_t>();
  if (in.take_bool()) {
    for (double& x : g.position_mm) x = in.take<double>();
    for (double& x : g.joints_rad) x = in.take<double>();
  }
  const int points = static_cast<int>(in.take_in(0, 5));
  for (int k = 0; k < points; ++k) {
    g.traj_t_s.push_back(in.take<float>());
    std::array<double, 6> q{}, qd{};
    for (double& x : q) x = in.take<double>();
    for (double& x : qd) x = in.take<double>();
    g.traj_q_rad.push_back(q);
    g.traj_qd_rad_s.push_back(qd);
  }
  return g;
}

using Identity = std::pair<int64_t, int64_t>;  // (goal_id, planned_utime)

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzBytes in(data, size);
  ephor::comm::RelayOptions options;
  options.preempt_in_flight = in.take_bool();
  options.wait_for_arm_state = in.take_bool();
  ephor::comm::GoalRelay relay(options);

  int64_t now_us = 1'000'000;
  int64_t last_first_seq = 0;
  std::map<int64_t, Identity> goal_of_seq;
  std::map<Identity, int64_t> done_at;  // identity -> number of goals finished when it was DONE
  int64_t finished = 0;

  for (int event = 0; event < 200 && !in.empty(); ++event) {
    now_us += in.take_in(0, 2'000'000);
    switch (in.take_in(0, 3)) {
      case 0:
        relay.submit(take_goal(in), now_us);
        break;
      case 1: {
        Ack ack;
        ack.seq = in.take_bool() ? relay.next_seq() - 1 - in.take_in(0, 2) : in.take<int64_t>();
        ack.goal_id = in.take_bool() ? in.take_in(0, 7) : in.take<int64_t>();
        ack.status = static_cast<AckStatus>(in.take_in(0, 3));
        ack.reason = in.take_string(32);
        ack.planned_duration_s = in.take<float>();
        relay.on_ack(ack, now_us);
        break;
      }
      case 2: {
        ephor::comm::ArmProgress p;
        p.executing_seq = in.take_bool() ? relay.next_seq() - in.take_in(0, 2) : in.take<int64_t>();
        p.last_done_seq = in.take_bool() ? relay.next_seq() - in.take_in(0, 2) : in.take<int64_t>();
        relay.on_arm_progress(p, now_us);
        break;
      }
      default: {
        const ephor::comm::RelayOutput out = relay.step(now_us);
        for (const auto& c : out.commands) {
          const Identity id{c.goal.goal_id, c.goal.planned_utime};
          if (c.transmission == 1) {
            if (goal_of_seq.count(c.seq) != 0)
              ephor::fuzz::fail("seq " + std::to_string(c.seq) + " sent first twice");
            if (c.seq <= last_first_seq)
              ephor::fuzz::fail("seq " + std::to_string(c.seq) + " after " +
                                std::to_string(last_first_seq));
            const auto done = done_at.find(id);
            if (done != done_at.end() && finished - done->second < options.finished_memory)
              ephor::fuzz::fail("goal " + std::to_string(id.first) +
                                " sent again after the arm reported it DONE");
            last_first_seq = c.seq;
            goal_of_seq[c.seq] = id;
          } else {
            const auto sent = goal_of_seq.find(c.seq);
            if (sent == goal_of_seq.end() || sent->second != id)
              ephor::fuzz::fail("retransmission of seq " + std::to_string(c.seq) +
                                " carries another goal");
          }
        }
        for (const auto& d : out.done) {
          ++finished;
          if (d.status == ephor::comm::Outcome::kDone) {
            // A DONE can come for a seq not yet sent under it: after a goal
            // moved to a fresh seq, an ack for that seq with the goal's id
            // (another comm sent it: the arm ran the goal) ends it DONE.
            const auto sent = goal_of_seq.find(d.seq);
            if (sent != goal_of_seq.end()) done_at[sent->second] = finished;
          }
        }
        break;
      }
    }
  }
  return 0;
}
