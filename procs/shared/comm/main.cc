// ephor-comm: the communication process between the planning host and the
// arm host (seed 003, section 3.3). The planner publishes ARM_GOAL and goes on
// planning; this process turns each goal into an ARM_CMD with a sequence
// number, retransmits until the arm answers on ARM_ACK, and reports how the
// goal ended on MOTION_DONE. The protocol is GoalRelay (procs/shared/comm/goal_relay.h);
// this file only converts LCM messages and drives it from a periodic task.
//
//   ephor-comm [--retry-ms 100] [--max-attempts 10] [--arm-name arm]
//
// Threads: the bus thread only queues what arrives (goals and acks in FIFOs,
// because every one of them matters; arm state in a newest-only mailbox) and
// never waits for the relay. The PERIODIC task "relay" (100 Hz) drives the
// GoalRelay: feeds it the queued inputs, advances its timers (retransmission,
// polls, timeouts) and publishes what it returns. A goal or an ack also
// releases the TRIGGERED task "relay_input", which runs the same job at once,
// so a goal reaches ARM_CMD (and an ack MOTION_DONE) without waiting up to a
// period: the capture-to-command latency target is 5 ms. A mutex
// keeps the two tasks from running the relay at the same time.

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/lcm/inbox.h"
#include "common/lcm/mailbox.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/time/clock.h"
#include "ephor/arm_ack_t.hpp"
#include "ephor/arm_cmd_t.hpp"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/motion_done_t.hpp"
#include "procs/shared/comm/goal_relay.h"

namespace {

constexpr const char* kRelayTask = "relay";
constexpr const char* kInputTask = "relay_input";

using ephor::comm::Ack;
using ephor::comm::AckStatus;
using ephor::comm::Command;
using ephor::comm::Goal;
using ephor::comm::MotionDone;
using ephor::comm::Outcome;

Goal to_goal(const ephor::arm_goal_t& m) {
  Goal g;
  g.goal_id = m.goal_id;
  g.planned_utime = m.utime;
  g.kind = m.kind;
  g.plane = m.plane;
  std::copy(m.position_mm, m.position_mm + 3, g.position_mm.begin());
  std::copy(m.joints_rad, m.joints_rad + 6, g.joints_rad.begin());
  g.u = m.u;
  g.v = m.v;
  g.theta_rad = m.theta_rad;
  g.max_speed_mm_s = m.max_speed_mm_s;
  g.source_frame_utime = m.source_frame_utime;
  g.target_object = m.target_object;
  // A trajectory's arrays as sent (num_points is checked by LCM's decoder
  // against the arrays; goal_problem() checks the rest).
  g.traj_t_s = m.traj_t_s;
  for (const auto& q : m.traj_q_rad) {
    std::array<double, 6> a{};
    std::copy_n(q.begin(), std::min<std::size_t>(6, q.size()), a.begin());
    g.traj_q_rad.push_back(a);
  }
  for (const auto& qd : m.traj_qd_rad_s) {
    std::array<double, 6> a{};
    std::copy_n(qd.begin(), std::min<std::size_t>(6, qd.size()), a.begin());
    g.traj_qd_rad_s.push_back(a);
  }
  return g;
}

// False (with `why`) for a status this comm does not know.
bool to_ack(const ephor::arm_ack_t& m, Ack& out, std::string& why) {
  switch (m.status) {
    case ephor::arm_ack_t::STATUS_ACCEPTED:
      out.status = AckStatus::kAccepted;
      break;
    case ephor::arm_ack_t::STATUS_DONE:
      out.status = AckStatus::kDone;
      break;
    case ephor::arm_ack_t::STATUS_REJECTED:
      out.status = AckStatus::kRejected;
      break;
    case ephor::arm_ack_t::STATUS_FAILED:
      out.status = AckStatus::kFailed;
      break;
    default:
      why = "unknown status " + std::to_string(static_cast<int>(m.status));
      return false;
  }
  out.seq = m.seq;
  out.goal_id = m.goal_id;
  out.reason = m.reason;
  out.planned_duration_s = m.planned_duration_s;
  return true;
}

// arm_cmd_t.utime is the wall time of a seq's FIRST send, the same in every
// retransmission and poll (lcmtypes/arm_cmd_t.lcm). The arm identifies a
// command by (seq, utime), so that a restarted comm's seqs are not mistaken
// for repeats, and checks the age of a command it has not seen yet. A fresh
// utime per transmission would make every retransmission a new command, to be
// executed again.
class FirstSendStamp {
 public:
  int64_t utime_for(int64_t seq) {
    if (seq != seq_) {
      seq_ = seq;
      utime_ = ephor::wall_us();
    }
    return utime_;
  }

 private:
  int64_t seq_ = 0;
  int64_t utime_ = 0;
};

ephor::arm_cmd_t to_cmd(const Command& c, int64_t first_sent_utime) {
  ephor::arm_cmd_t m{};
  m.utime = first_sent_utime;
  m.seq = c.seq;
  m.goal_id = c.goal.goal_id;
  m.kind = c.goal.kind;
  m.plane = c.goal.plane;
  std::copy(c.goal.position_mm.begin(), c.goal.position_mm.end(), m.position_mm);
  std::copy(c.goal.joints_rad.begin(), c.goal.joints_rad.end(), m.joints_rad);
  m.u = c.goal.u;
  m.v = c.goal.v;
  m.theta_rad = c.goal.theta_rad;
  m.max_speed_mm_s = c.goal.max_speed_mm_s;
  m.source_frame_utime = c.goal.source_frame_utime;
  m.num_points = static_cast<int32_t>(c.goal.traj_t_s.size());
  m.traj_t_s = c.goal.traj_t_s;
  for (const auto& q : c.goal.traj_q_rad) m.traj_q_rad.emplace_back(q.begin(), q.end());
  for (const auto& qd : c.goal.traj_qd_rad_s) m.traj_qd_rad_s.emplace_back(qd.begin(), qd.end());
  return m;
}

int8_t to_msg_status(Outcome o) {
  switch (o) {
    case Outcome::kDone:
      return ephor::motion_done_t::STATUS_DONE;
    case Outcome::kRejected:
      return ephor::motion_done_t::STATUS_REJECTED;
    case Outcome::kFailed:
      return ephor::motion_done_t::STATUS_FAILED;
    case Outcome::kTimeout:
      return ephor::motion_done_t::STATUS_TIMEOUT;
  }
  return ephor::motion_done_t::STATUS_FAILED;
}

ephor::motion_done_t to_msg(const MotionDone& d) {
  ephor::motion_done_t m{};
  m.utime = ephor::wall_us();
  m.goal_id = d.goal_id;
  m.seq = d.seq;
  m.status = to_msg_status(d.status);
  m.reason = d.reason;
  m.attempts = d.attempts;
  return m;
}

// Counts messages from a sender other than the expected one; warns on the
// first and then every 100th so a misconfigured host is visible but not noisy.
class ForeignSenders {
 public:
  explicit ForeignSenders(std::string channel) : channel_(std::move(channel)) {}
  void note(const std::string& sender, const std::string& expected) {
    const uint64_t n = ++count_;
    if (n == 1 || n % 100 == 0)
      spdlog::warn("{}: ignored message from sender '{}' (expected '{}'; {} ignored so far)",
                   channel_, sender, expected, n);
  }
  uint64_t count() const { return count_.load(); }

 private:
  std::string channel_;
  std::atomic<uint64_t> count_{0};
};

}  // namespace

int main(int argc, char** argv) {
  ephor::block_shutdown_signals();
  CLI::App app{"ephor-comm: relays planner goals to the arm with retransmission (seed 003, 3.3)"};
  ephor::ProcessArgs args;
  ephor::add_process_flags(app, args, "comm");
  int retry_ms = 100;
  int max_attempts = 10;
  int poll_ms = 200;
  int done_margin_ms = 1000;
  std::string arm_name = "arm";
  bool preempt = false;
  double duration_s = 0.0;
  app.add_option("--retry-ms", retry_ms,
                 "re-send a command every this many ms until the arm answers")
      ->check(CLI::Range(1, 60'000))
      ->capture_default_str();
  app.add_option("--max-attempts", max_attempts,
                 "sends without an answer before a goal ends TIMEOUT")
      ->check(CLI::Range(1, 10'000))
      ->capture_default_str();
  app.add_option("--poll-ms", poll_ms,
                 "while a motion runs, re-send its command every this many ms")
      ->check(CLI::Range(1, 60'000))
      ->capture_default_str();
  app.add_option("--done-margin-ms", done_margin_ms,
                 "wait this long (plus 50 % of the planned duration) past the planned end for DONE")
      ->check(CLI::Range(0, 600'000))
      ->capture_default_str();
  app.add_option("--arm-name", arm_name,
                 "sender name of the arm process; acks and state from others are ignored")
      ->capture_default_str();
  app.add_flag("--preempt", preempt,
               "a newer goal replaces the motion in progress once the arm has accepted it "
               "(catching); default: each motion ends first (shepherding)");
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  ephor::init_logging(args.name);

  try {
    ephor::comm::RelayOptions options;
    options.preempt_in_flight = preempt;
    options.retry_interval_us = int64_t{retry_ms} * 1000;
    options.max_attempts = max_attempts;
    options.poll_interval_us = int64_t{poll_ms} * 1000;
    options.done_margin_us = int64_t{done_margin_ms} * 1000;
    ephor::comm::GoalRelay relay(options);  // only the relay task touches it after start()

    // Everything the bus callbacks touch is declared before the bus, so it
    // outlives the bus thread.
    ephor::Inbox<ephor::arm_goal_t> goals(256);
    ephor::Inbox<ephor::arm_ack_t> acks(1024);
    auto arm_state = std::make_shared<ephor::Mailbox<ephor::arm_state_t>>();
    ForeignSenders foreign_acks(ephor::channels::kArmAck);
    ForeignSenders foreign_states(ephor::channels::kArmState);

    ephor::Bus bus(args.lcm_url, args.name);
    ephor::TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    // The callbacks also trigger `runtime`, which dies before `bus`; and
    // TaskRuntime::stop() leaves the bus thread running. Stop the bus before
    // either goes, also when an exception unwinds this scope.
    struct StopBusFirst {
      ephor::Bus& bus;
      ~StopBusFirst() { bus.stop(); }
    } stop_bus_first{bus};
    bus.subscribe<ephor::arm_goal_t>(ephor::channels::kArmGoal, [&](const ephor::arm_goal_t& m) {
      goals.push(m);
      runtime.trigger(kInputTask);
    });
    bus.subscribe<ephor::arm_ack_t>(ephor::channels::kArmAck, [&](const ephor::arm_ack_t& m) {
      if (m.header.sender == arm_name) {
        acks.push(m);
        runtime.trigger(kInputTask);
      } else {
        foreign_acks.note(m.header.sender, arm_name);
      }
    });
    bus.subscribe<ephor::arm_state_t>(ephor::channels::kArmState, [&](const ephor::arm_state_t& m) {
      if (m.header.sender == arm_name) {
        arm_state->put(m);
      } else {
        foreign_states.note(m.header.sender, arm_name);
      }
    });

    // Both tasks run this job; the mutex makes them one relay.
    std::mutex relay_mutex;
    uint64_t bad_acks = 0;  // guarded by relay_mutex
    FirstSendStamp stamp;   // guarded by relay_mutex
    bool announced_arm = false;
    auto relay_job = [&] {
      std::lock_guard<std::mutex> lock(relay_mutex);
      const int64_t now = ephor::mono_us();
      if (auto s = arm_state->take()) {
        if (!announced_arm) {
          spdlog::info("arm '{}' heard: executing seq {}, last done seq {}", arm_name,
                       s->executing_seq, s->last_done_seq);
          announced_arm = true;
        }
        relay.on_arm_progress({s->executing_seq, s->last_done_seq}, now);
      }
      for (const ephor::arm_ack_t& m : acks.drain()) {
        Ack ack;
        std::string why;
        if (!to_ack(m, ack, why)) {
          ++bad_acks;
          spdlog::warn("ARM_ACK for seq {} ignored: {} ({} bad acks)", m.seq, why, bad_acks);
          continue;
        }
        relay.on_ack(ack, now);
      }
      for (const ephor::arm_goal_t& m : goals.drain()) relay.submit(to_goal(m), now);

      ephor::comm::RelayOutput out = relay.step(now);
      for (const Command& c : out.commands) {
        ephor::arm_cmd_t msg = to_cmd(c, stamp.utime_for(c.seq));
        bus.publish(ephor::channels::kArmCmd, msg);
      }
      for (const MotionDone& d : out.done) {
        ephor::motion_done_t msg = to_msg(d);
        bus.publish(ephor::channels::kMotionDone, msg);
        const auto level = d.status == Outcome::kDone ? spdlog::level::info : spdlog::level::warn;
        spdlog::log(level, "goal {} seq {}: {} after {} attempt(s), round trip {:.1f} ms{}{}",
                    d.goal_id, d.seq, ephor::comm::to_string(d.status), d.attempts,
                    static_cast<double>(d.round_trip_us) / 1000.0, d.reason.empty() ? "" : ": ",
                    d.reason);
      }
      for (const ephor::comm::LateConfirmation& l : out.late)
        spdlog::warn("goal {} seq {}: late {} {:.1f} ms after it was reported TIMEOUT{}{}",
                     l.goal_id, l.seq, ephor::comm::to_string(l.status),
                     static_cast<double>(l.after_timeout_us) / 1000.0, l.reason.empty() ? "" : ": ",
                     l.reason);
    };

    runtime.add_periodic(kRelayTask, std::chrono::milliseconds(10), relay_job);
    runtime.add_triggered(kInputTask, std::chrono::milliseconds(10), relay_job);
    runtime.start();
    spdlog::info("relaying {} -> {} (arm '{}', retry {} ms x {}, poll {} ms)",
                 ephor::channels::kArmGoal, ephor::channels::kArmCmd, arm_name, retry_ms,
                 max_attempts, poll_ms);
    ephor::wait_for_shutdown_signal(duration_s);
    runtime.stop();
    bus.stop();  // no callback after this: the counters below are final

    const ephor::comm::RelayCounters& c = relay.counters();
    spdlog::info(
        "goals {} (invalid {}, superseded {}, duplicate {}); commands {} + {} retransmissions + {} "
        "polls; "
        "done {}, rejected {}, failed {}, timeout {}; acks unknown {}, duplicate {}, late {}, bad "
        "{}; implausible seqs {}; "
        "foreign senders: acks {}, states {}; inbox drops: goals {}, acks {}",
        c.goals_received, c.goals_invalid, c.goals_superseded, c.goals_duplicate, c.commands_sent,
        c.retransmissions, c.polls, c.done, c.rejected, c.failed, c.timeouts, c.acks_unknown,
        c.acks_duplicate, c.late_confirmations, bad_acks, c.implausible_seqs, foreign_acks.count(),
        foreign_states.count(), goals.dropped(), acks.dropped());
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
