#include "procs/shared/comm/goal_relay.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace ephor::comm {
namespace {

constexpr int64_t kMs = 1000;  // us per ms

Goal make_goal(int64_t id, float u = 100.0f, float v = 200.0f) {
  Goal g;
  g.goal_id = id;
  g.planned_utime = 1'000'000 + id;
  g.plane = static_cast<int8_t>(Plane::kElevation);
  g.u = u;
  g.v = v;
  g.theta_rad = 0.5f;
  return g;
}

Ack make_ack(const Command& c, AckStatus status, float planned_s = 0.0f, std::string reason = "") {
  return Ack{c.seq, c.goal.goal_id, status, std::move(reason), planned_s};
}

// A relay that has heard the arm (seq unknown -> starts at 1).
GoalRelay ready_relay(RelayOptions o = {}) {
  GoalRelay r(o);
  r.on_arm_progress({0, 0}, 0);
  return r;
}

TEST(GoalRelayTest, HappyPathInOrder) {
  GoalRelay relay = ready_relay();
  std::vector<int64_t> seqs;
  int64_t t = 0;
  for (int64_t id = 1; id <= 3; ++id) {
    relay.submit(make_goal(id), t);
    RelayOutput out = relay.step(t);
    ASSERT_EQ(out.commands.size(), 1u);
    const Command cmd = out.commands[0];
    EXPECT_EQ(cmd.goal.goal_id, id);
    EXPECT_EQ(cmd.transmission, 1);
    seqs.push_back(cmd.seq);
    t += 20 * kMs;
    relay.on_ack(make_ack(cmd, AckStatus::kAccepted, 0.5f), t);
    EXPECT_TRUE(relay.step(t).commands.empty()) << "no retransmission once accepted";
    t += 500 * kMs;
    relay.on_ack(make_ack(cmd, AckStatus::kDone), t);
    out = relay.step(t);
    ASSERT_EQ(out.done.size(), 1u);
    EXPECT_EQ(out.done[0].goal_id, id);
    EXPECT_EQ(out.done[0].seq, cmd.seq);
    EXPECT_EQ(out.done[0].status, Outcome::kDone);
    EXPECT_EQ(out.done[0].attempts, 1);
    EXPECT_EQ(out.done[0].round_trip_us, 520 * kMs);
    EXPECT_FALSE(relay.busy());
  }
  EXPECT_EQ(seqs, (std::vector<int64_t>{1, 2, 3}));
  EXPECT_EQ(relay.counters().goals_received, 3);
  EXPECT_EQ(relay.counters().commands_sent, 3);
  EXPECT_EQ(relay.counters().retransmissions, 0);
  EXPECT_EQ(relay.counters().done, 3);
}

TEST(GoalRelayTest, UnansweredCommandIsRetransmittedThenTimesOut) {
  RelayOptions o;
  o.retry_interval_us = 100 * kMs;
  o.max_attempts = 3;
  GoalRelay relay = ready_relay(o);
  relay.submit(make_goal(7), 0);
  std::vector<int64_t> send_times;
  std::optional<MotionDone> done;
  for (int64_t t = 0; t <= 1000 * kMs && !done; t += 10 * kMs) {
    RelayOutput out = relay.step(t);
    for (const Command& c : out.commands) {
      EXPECT_EQ(c.seq, 1);
      send_times.push_back(t);
    }
    if (!out.done.empty()) done = out.done[0];
  }
  EXPECT_EQ(send_times, (std::vector<int64_t>{0, 100 * kMs, 200 * kMs}));
  ASSERT_TRUE(done);
  EXPECT_EQ(done->status, Outcome::kTimeout);
  EXPECT_EQ(done->attempts, 3);
  EXPECT_EQ(done->round_trip_us, 300 * kMs);
  EXPECT_EQ(relay.counters().retransmissions, 2);
  EXPECT_EQ(relay.counters().timeouts, 1);
}

TEST(GoalRelayTest, AcceptedButNoDoneTimesOutAfterPlannedDurationPlusMargin) {
  RelayOptions o;
  o.done_margin_factor = 0.5;
  o.done_margin_us = 1000 * kMs;
  GoalRelay relay = ready_relay(o);
  relay.submit(make_goal(1), 0);
  const Command cmd = relay.step(0).commands.at(0);
  relay.on_ack(make_ack(cmd, AckStatus::kAccepted, 2.0f), 0);
  // Deadline: 2 s * 1.5 + 1 s = 4 s after ACCEPTED. Polls keep going meanwhile.
  int polls = 0;
  std::optional<MotionDone> done;
  int64_t t = 0;
  for (; t <= 10'000 * kMs && !done; t += 10 * kMs) {
    RelayOutput out = relay.step(t);
    for (const Command& c : out.commands) {
      EXPECT_EQ(c.seq, cmd.seq) << "a poll repeats the same seq";
      ++polls;
    }
    if (!out.done.empty()) done = out.done[0];
  }
  ASSERT_TRUE(done);
  EXPECT_EQ(done->status, Outcome::kTimeout);
  EXPECT_EQ(t - 10 * kMs, 4000 * kMs);
  EXPECT_EQ(done->attempts, 1) << "polls after ACCEPTED are not delivery attempts";
  EXPECT_GT(polls, 0);
  EXPECT_EQ(relay.counters().polls, polls);

  // The DONE arrives after all: reported as a late confirmation, not a second outcome.
  relay.on_ack(make_ack(cmd, AckStatus::kDone), t + 100 * kMs);
  relay.on_ack(make_ack(cmd, AckStatus::kDone), t + 110 * kMs);
  RelayOutput out = relay.step(t + 120 * kMs);
  EXPECT_TRUE(out.done.empty());
  ASSERT_EQ(out.late.size(), 1u);
  EXPECT_EQ(out.late[0].status, AckStatus::kDone);
  EXPECT_EQ(relay.counters().late_confirmations, 1);
  EXPECT_EQ(relay.counters().acks_duplicate, 1);
}

TEST(GoalRelayTest, LostDoneIsRecoveredByPolling) {
  GoalRelay relay = ready_relay();
  relay.submit(make_goal(1), 0);
  const Command cmd = relay.step(0).commands.at(0);
  relay.on_ack(make_ack(cmd, AckStatus::kAccepted, 0.3f), 5 * kMs);
  // The arm finished at 300 ms but its DONE was lost; it answers the next poll.
  std::optional<MotionDone> done;
  for (int64_t t = 10 * kMs; t <= 2000 * kMs && !done; t += 10 * kMs) {
    RelayOutput out = relay.step(t);
    for (const Command& c : out.commands)
      if (t > 300 * kMs) relay.on_ack(make_ack(c, AckStatus::kDone), t);
    if (!out.done.empty()) done = out.done[0];
  }
  ASSERT_TRUE(done);
  EXPECT_EQ(done->status, Outcome::kDone);
  EXPECT_LE(done->round_trip_us, 300 * kMs + 200 * kMs + 10 * kMs);
}

TEST(GoalRelayTest, RejectedGoalIsReportedWithTheArmsReason) {
  GoalRelay relay = ready_relay();
  relay.submit(make_goal(4, 9000.0f, 9000.0f), 0);
  const Command cmd = relay.step(0).commands.at(0);
  relay.on_ack(
      make_ack(cmd, AckStatus::kRejected, 0.0f, "target (9000, 9000) px is outside the field"),
      15 * kMs);
  RelayOutput out = relay.step(20 * kMs);
  ASSERT_EQ(out.done.size(), 1u);
  EXPECT_EQ(out.done[0].goal_id, 4);
  EXPECT_EQ(out.done[0].status, Outcome::kRejected);
  EXPECT_EQ(out.done[0].reason, "target (9000, 9000) px is outside the field");
  EXPECT_EQ(out.done[0].attempts, 1);
  EXPECT_TRUE(relay.step(500 * kMs).commands.empty()) << "a rejected command is not retransmitted";
}

TEST(GoalRelayTest, FailedGoalIsReported) {
  GoalRelay relay = ready_relay();
  relay.submit(make_goal(4), 0);
  const Command cmd = relay.step(0).commands.at(0);
  relay.on_ack(make_ack(cmd, AckStatus::kAccepted, 1.0f), 10 * kMs);
  relay.on_ack(make_ack(cmd, AckStatus::kFailed, 0.0f, "estop"), 400 * kMs);
  RelayOutput out = relay.step(400 * kMs);
  ASSERT_EQ(out.done.size(), 1u);
  EXPECT_EQ(out.done[0].status, Outcome::kFailed);
  EXPECT_EQ(out.done[0].reason, "estop");
}

TEST(GoalRelayTest, InvalidGoalIsRejectedAtOnceAndNeverSent) {
  GoalRelay relay = ready_relay();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<Goal> bad = {make_goal(1, nan), make_goal(2, 1.0f, inf),
                           make_goal(3),      make_goal(4),
                           make_goal(5),      make_goal(-6)};
  bad[2].theta_rad = nan;
  bad[3].plane = 7;
  bad[4].max_speed_mm_s = -1.0f;
  for (const Goal& g : bad) relay.submit(g, 0);
  RelayOutput out = relay.step(0);
  EXPECT_TRUE(out.commands.empty());
  ASSERT_EQ(out.done.size(), bad.size());
  for (size_t i = 0; i < bad.size(); ++i) {
    EXPECT_EQ(out.done[i].goal_id, bad[i].goal_id);
    EXPECT_EQ(out.done[i].status, Outcome::kRejected);
    EXPECT_EQ(out.done[i].seq, 0);
    EXPECT_EQ(out.done[i].attempts, 0);
    EXPECT_EQ(out.done[i].reason.rfind("invalid goal: ", 0), 0u) << out.done[i].reason;
  }
  EXPECT_NE(out.done[0].reason.find("not finite"), std::string::npos) << out.done[0].reason;
  EXPECT_NE(out.done[3].reason.find("plane 7"), std::string::npos) << out.done[3].reason;
  EXPECT_EQ(relay.counters().goals_invalid, 6);
  EXPECT_EQ(relay.counters().commands_sent, 0);
  EXPECT_EQ(relay.next_seq(), 1) << "an invalid goal uses no seq";
}

TEST(GoalRelayTest, InvalidGoalDoesNotDisturbTheQueuedOne) {
  GoalRelay relay = ready_relay();
  relay.submit(make_goal(1), 0);
  relay.submit(make_goal(2, std::nanf("")), 0);
  RelayOutput out = relay.step(0);
  ASSERT_EQ(out.commands.size(), 1u);
  EXPECT_EQ(out.commands[0].goal.goal_id, 1);
}

TEST(GoalRelayTest, SupersededGoalIsNeverSent) {
  GoalRelay relay = ready_relay();
  relay.submit(make_goal(1), 0);
  const Command first = relay.step(0).commands.at(0);
  // While 1 is in flight, 2 then 3 arrive: 3 replaces 2, 1 is not aborted.
  relay.submit(make_goal(2), 10 * kMs);
  relay.submit(make_goal(3), 20 * kMs);
  EXPECT_EQ(relay.counters().goals_superseded, 1);
  relay.on_ack(make_ack(first, AckStatus::kAccepted, 0.1f), 30 * kMs);
  EXPECT_TRUE(relay.step(30 * kMs).commands.empty());
  relay.on_ack(make_ack(first, AckStatus::kDone), 140 * kMs);
  RelayOutput out = relay.step(140 * kMs);
  ASSERT_EQ(out.done.size(), 1u);
  EXPECT_EQ(out.done[0].goal_id, 1);
  ASSERT_EQ(out.commands.size(), 1u);
  EXPECT_EQ(out.commands[0].goal.goal_id, 3);
  EXPECT_EQ(out.commands[0].seq, first.seq + 1);

  // Also before anything was sent: two goals in one cycle, only the newest goes.
  GoalRelay idle = ready_relay();
  idle.submit(make_goal(10), 0);
  idle.submit(make_goal(11), 1);
  out = idle.step(2);
  ASSERT_EQ(out.commands.size(), 1u);
  EXPECT_EQ(out.commands[0].goal.goal_id, 11);
}

TEST(GoalRelayTest, RepublishedGoalIsNotExecutedTwice) {
  GoalRelay relay = ready_relay();
  const Goal g = make_goal(1);
  relay.submit(g, 0);
  const Command cmd = relay.step(0).commands.at(0);
  relay.submit(g, 5 * kMs);  // while in flight
  relay.on_ack(make_ack(cmd, AckStatus::kDone), 10 * kMs);
  ASSERT_EQ(relay.step(10 * kMs).done.size(), 1u);
  relay.submit(g, 20 * kMs);  // after it finished
  EXPECT_TRUE(relay.step(20 * kMs).commands.empty());
  EXPECT_EQ(relay.counters().goals_duplicate, 2);
  // A restarted planner's goal 1 is planned at another time: it is a new goal.
  Goal again = g;
  again.planned_utime += 5'000'000;
  relay.submit(again, 30 * kMs);
  EXPECT_EQ(relay.step(30 * kMs).commands.size(), 1u);
}

TEST(GoalRelayTest, RestartPicksSeqAboveTheArmsLastSeq) {
  GoalRelay relay;  // a freshly restarted comm
  relay.submit(make_goal(1), 0);
  EXPECT_TRUE(relay.step(0).commands.empty()) << "held until the arm's seq is known";
  relay.on_arm_progress({0, 41}, 5 * kMs);
  RelayOutput out = relay.step(10 * kMs);
  ASSERT_EQ(out.commands.size(), 1u);
  EXPECT_EQ(out.commands[0].seq, 42);

  GoalRelay moving;  // restarted while the arm still executes the old comm's seq 57
  moving.on_arm_progress({57, 56}, 0);
  moving.submit(make_goal(1), 0);
  EXPECT_EQ(moving.step(0).commands.at(0).seq, 58);
}

// Found by fuzz_comm_goal_relay: an arm state (or ack) with seq 2^63 - 1
// made the next seq overflow (UB; in practice negative seqs). A seq no arm
// reaches is ignored, counted, and the relay goes on with its own numbering.
TEST(GoalRelayTest, ImplausibleSeqsFromTheArmAreIgnoredNotFollowed) {
  GoalRelay relay = ready_relay();
  relay.on_arm_progress({INT64_MAX, INT64_MAX}, 0);
  relay.on_arm_progress({-5, -7}, 0);
  relay.on_ack(Ack{INT64_MAX, 9, AckStatus::kDone, "", 0.0f}, 0);
  EXPECT_EQ(relay.counters().implausible_seqs, 3);
  relay.submit(make_goal(1), 0);
  const RelayOutput out = relay.step(0);
  ASSERT_EQ(out.commands.size(), 1u);
  EXPECT_EQ(out.commands[0].seq, 1);
}

TEST(GoalRelayTest, NoArmHeardEndsTheGoalAsTimeout) {
  RelayOptions o;
  o.retry_interval_us = 100 * kMs;
  o.max_attempts = 5;
  GoalRelay relay(o);
  relay.submit(make_goal(9), 0);
  EXPECT_TRUE(relay.step(499 * kMs).done.empty());
  RelayOutput out = relay.step(500 * kMs);
  ASSERT_EQ(out.done.size(), 1u);
  EXPECT_EQ(out.done[0].status, Outcome::kTimeout);
  EXPECT_EQ(out.done[0].attempts, 0);
  EXPECT_TRUE(out.commands.empty());
}

TEST(GoalRelayTest, UnknownAndOldAcksAreCountedAndIgnored) {
  GoalRelay relay = ready_relay();
  relay.submit(make_goal(1), 0);
  const Command cmd = relay.step(0).commands.at(0);
  relay.on_ack(Ack{99, 5, AckStatus::kDone, "", 0.0f}, 1 * kMs);  // a seq never sent
  RelayOutput out = relay.step(2 * kMs);
  EXPECT_TRUE(out.done.empty()) << "goal 1 is still in flight";
  EXPECT_EQ(relay.counters().acks_unknown, 1);
  EXPECT_EQ(relay.next_seq(), 100) << "a seq the arm has seen is never reused";

  relay.on_ack(make_ack(cmd, AckStatus::kAccepted, 0.1f), 3 * kMs);
  relay.on_ack(make_ack(cmd, AckStatus::kAccepted, 0.1f), 4 * kMs);  // duplicate
  relay.on_ack(make_ack(cmd, AckStatus::kDone), 110 * kMs);
  relay.on_ack(make_ack(cmd, AckStatus::kDone), 111 * kMs);  // duplicate of a finished seq
  out = relay.step(120 * kMs);
  ASSERT_EQ(out.done.size(), 1u);
  EXPECT_EQ(relay.counters().acks_duplicate, 2);
  EXPECT_TRUE(out.late.empty());
}

TEST(GoalRelayTest, InFlightSeqAnsweredForAnotherGoalMovesToAFreshSeq) {
  GoalRelay relay = ready_relay();
  relay.submit(make_goal(1), 0);
  const Command cmd = relay.step(0).commands.at(0);
  // The arm already executed seq 1 for another comm's goal 77.
  relay.on_ack(Ack{cmd.seq, 77, AckStatus::kDone, "", 0.0f}, 5 * kMs);
  RelayOutput out = relay.step(10 * kMs);
  EXPECT_TRUE(out.done.empty());
  ASSERT_EQ(out.commands.size(), 1u);
  EXPECT_EQ(out.commands[0].goal.goal_id, 1);
  EXPECT_GT(out.commands[0].seq, cmd.seq);
  // The fresh seq's first send is its first transmission, not a retransmission
  // (found by the fuzz target comm_goal_relay).
  EXPECT_EQ(out.commands[0].transmission, 1);
  EXPECT_EQ(relay.counters().commands_sent, 2);
  EXPECT_EQ(relay.counters().retransmissions, 0);
  EXPECT_EQ(relay.counters().seq_conflicts, 1);
}

TEST(GoalRelayTest, AnArmThatNeverEchoesTheGoalIdEndsTheGoalFailedInsteadOfResendingForever) {
  GoalRelay relay = ready_relay();
  relay.submit(make_goal(1), 0);
  std::vector<int64_t> seqs;
  std::optional<MotionDone> done;
  for (int64_t t = 0; t < 5000 * kMs && !done; t += 10 * kMs) {
    RelayOutput out = relay.step(t);
    for (const Command& c : out.commands) {
      if (seqs.empty() || seqs.back() != c.seq) seqs.push_back(c.seq);
      relay.on_ack(Ack{c.seq, 0, AckStatus::kAccepted, "", 1.0f}, t);  // goal_id always 0
    }
    if (!out.done.empty()) done = out.done[0];
  }
  ASSERT_TRUE(done);
  EXPECT_EQ(done->status, Outcome::kFailed);
  EXPECT_NE(done->reason.find("acks do not match commands"), std::string::npos) << done->reason;
  EXPECT_EQ(seqs.size(), 3u) << "the first seq and two moves";
}

TEST(GoalRelayTest, BadOptionsAreRefusedWithTheirName) {
  RelayOptions o;
  o.max_attempts = 0;
  EXPECT_THROW(
      {
        try {
          GoalRelay r(o);
        } catch (const std::invalid_argument& e) {
          EXPECT_NE(std::string(e.what()).find("max attempts"), std::string::npos);
          throw;
        }
      },
      std::invalid_argument);
  o = {};
  o.retry_interval_us = 0;
  EXPECT_THROW(GoalRelay{o}, std::invalid_argument);
}

// ---------------------------------------------------------------------------
// A lossy link and an arm that executes each seq at most once, in simulated
// time, to check the protocol end to end.

struct LinkOptions {
  double loss = 0.05;  // fraction dropped, each direction independently
  int64_t min_delay_us = 2 * kMs;
  int64_t max_delay_us = 60 * kMs;
};

// Messages in transit with a random delay, dropped with a fixed probability.
template <class T>
class LossyLink {
 public:
  LossyLink(LinkOptions o, std::mt19937_64& rng) : o_(o), rng_(rng) {}
  void send(const T& msg, int64_t now_us) {
    ++sent_;
    if (std::bernoulli_distribution(o_.loss)(rng_)) {
      ++dropped_;
      return;
    }
    const int64_t delay =
        std::uniform_int_distribution<int64_t>(o_.min_delay_us, o_.max_delay_us)(rng_);
    in_transit_.emplace(now_us + delay, msg);
  }
  // Messages whose arrival time has come, in arrival order.
  std::vector<T> receive(int64_t now_us) {
    std::vector<T> out;
    while (!in_transit_.empty() && in_transit_.begin()->first <= now_us) {
      out.push_back(in_transit_.begin()->second);
      in_transit_.erase(in_transit_.begin());
    }
    return out;
  }
  int64_t dropped() const { return dropped_; }

 private:
  LinkOptions o_;
  std::mt19937_64& rng_;
  std::multimap<int64_t, T> in_transit_;
  int64_t sent_ = 0;
  int64_t dropped_ = 0;
};

// The arm's contract: executes each seq at most once, one motion at a time (a
// new seq preempts the running motion, which ends FAILED), answers a repeated
// seq with its newest ack for it.
class SimulatedArm {
 public:
  explicit SimulatedArm(std::mt19937_64& rng) : rng_(rng) {}

  void receive(const Command& cmd, int64_t now_us, LossyLink<Ack>& acks) {
    auto it = last_ack_.find(cmd.seq);
    if (it != last_ack_.end()) {
      acks.send(it->second, now_us);
      return;
    }
    if (current_) finish(AckStatus::kFailed, "preempted by a newer command", now_us, acks);
    ++executions_[cmd.seq];
    ++executions_of_goal_[cmd.goal.goal_id];
    const float duration_s = std::uniform_real_distribution<float>(0.05f, 1.5f)(rng_);
    current_ = Motion{cmd.seq, cmd.goal.goal_id, now_us + static_cast<int64_t>(duration_s * 1e6f)};
    answer(Ack{cmd.seq, cmd.goal.goal_id, AckStatus::kAccepted, "", duration_s}, now_us, acks);
  }
  void step(int64_t now_us, LossyLink<Ack>& acks) {
    if (current_ && now_us >= current_->end_us) finish(AckStatus::kDone, "", now_us, acks);
  }
  ArmProgress progress() const { return {current_ ? current_->seq : 0, last_done_seq_}; }
  const std::map<int64_t, int>& executions() const { return executions_; }
  const std::map<int64_t, int>& executions_of_goal() const { return executions_of_goal_; }

 private:
  struct Motion {
    int64_t seq;
    int64_t goal_id;
    int64_t end_us;
  };
  void answer(const Ack& ack, int64_t now_us, LossyLink<Ack>& acks) {
    last_ack_[ack.seq] = ack;
    acks.send(ack, now_us);
  }
  void finish(AckStatus status, const char* reason, int64_t now_us, LossyLink<Ack>& acks) {
    answer(Ack{current_->seq, current_->goal_id, status, reason, 0.0f}, now_us, acks);
    last_done_seq_ = current_->seq;
    current_.reset();
  }
  std::mt19937_64& rng_;
  std::optional<Motion> current_;
  std::map<int64_t, Ack> last_ack_;
  std::map<int64_t, int> executions_;
  std::map<int64_t, int> executions_of_goal_;
  int64_t last_done_seq_ = 0;
};

struct LossyRun {
  std::map<int64_t, std::vector<MotionDone>> outcomes;  // per goal id
  std::map<int64_t, int> executions_per_seq;
  std::map<int64_t, int> executions_per_goal;
  RelayCounters counters;
  int64_t dropped = 0;
};

// The planner sends goals 1..n one after the other (the next when the last
// one's motion_done arrives), over a lossy link, 10 ms relay cycles.
LossyRun run_lossy(int n_goals, RelayOptions options, LinkOptions link, uint64_t seed) {
  std::mt19937_64 rng(seed);
  LossyLink<Command> to_arm(link, rng);
  LossyLink<Ack> to_comm(link, rng);
  SimulatedArm arm(rng);
  GoalRelay relay(options);
  LossyRun run;
  int64_t next_goal = 1;
  bool waiting = false;
  const int64_t cycle_us = 10 * kMs;
  for (int64_t t = 0; next_goal <= n_goals || waiting; t += cycle_us) {
    if (t > static_cast<int64_t>(n_goals) * 60'000 * kMs) {
      ADD_FAILURE() << "simulation did not finish";
      break;
    }
    arm.step(t, to_comm);
    relay.on_arm_progress(arm.progress(), t);  // arm state (loss-free: 100 Hz, full state)
    for (const Ack& a : to_comm.receive(t)) relay.on_ack(a, t);
    if (!waiting && next_goal <= n_goals) {
      relay.submit(make_goal(next_goal++), t);
      waiting = true;
    }
    RelayOutput out = relay.step(t);
    for (const Command& c : out.commands) to_arm.send(c, t);
    for (const MotionDone& d : out.done) {
      run.outcomes[d.goal_id].push_back(d);
      waiting = false;
    }
    for (const Command& c : to_arm.receive(t)) arm.receive(c, t, to_comm);
  }
  run.executions_per_seq = arm.executions();
  run.executions_per_goal = arm.executions_of_goal();
  run.counters = relay.counters();
  run.dropped = to_arm.dropped() + to_comm.dropped();
  return run;
}

TEST(GoalRelayLossTest, ThousandGoalsOverFivePercentLossAreEachDoneExactlyOnce) {
  RelayOptions o;  // defaults: 100 ms retry, 10 attempts
  const LossyRun run = run_lossy(1000, o, LinkOptions{}, 20261122);
  ASSERT_EQ(run.outcomes.size(), 1000u);
  for (const auto& [goal, outcomes] : run.outcomes) {
    ASSERT_EQ(outcomes.size(), 1u) << "goal " << goal << " reported more than once";
    EXPECT_EQ(outcomes[0].status, Outcome::kDone) << "goal " << goal << ": " << outcomes[0].reason;
  }
  for (const auto& [seq, n] : run.executions_per_seq) EXPECT_EQ(n, 1) << "seq " << seq;
  ASSERT_EQ(run.executions_per_goal.size(), 1000u);
  for (const auto& [goal, n] : run.executions_per_goal) EXPECT_EQ(n, 1) << "goal " << goal;
  EXPECT_GT(run.dropped, 0) << "the link did drop messages";
  EXPECT_GT(run.counters.retransmissions, 0) << "losses were recovered by retransmitting";
  EXPECT_EQ(run.counters.done, 1000);
  std::printf(
      "1000 goals, 5%% loss each way: %lld dropped, %lld retransmissions, %lld polls, %lld "
      "duplicate acks\n",
      static_cast<long long>(run.dropped), static_cast<long long>(run.counters.retransmissions),
      static_cast<long long>(run.counters.polls),
      static_cast<long long>(run.counters.acks_duplicate));
}

TEST(GoalRelayLossTest, WithATinyRetryBudgetEveryGoalEndsDoneOrTimeoutAndRunsAtMostOnce) {
  RelayOptions o;
  o.max_attempts = 1;  // no retransmission: some goals must time out
  o.done_margin_us = 100 * kMs;
  o.done_margin_factor = 0.0;
  LinkOptions link;
  link.loss = 0.2;
  const LossyRun run = run_lossy(1000, o, link, 7);
  ASSERT_EQ(run.outcomes.size(), 1000u);
  int done = 0;
  int timeout = 0;
  for (const auto& [goal, outcomes] : run.outcomes) {
    ASSERT_EQ(outcomes.size(), 1u) << "goal " << goal;
    const Outcome s = outcomes[0].status;
    // FAILED is the simulated arm preempting a motion whose comm gave up.
    EXPECT_TRUE(s == Outcome::kDone || s == Outcome::kTimeout || s == Outcome::kFailed)
        << "goal " << goal << " ended " << to_string(s);
    done += s == Outcome::kDone;
    timeout += s == Outcome::kTimeout;
  }
  EXPECT_GT(timeout, 0);
  EXPECT_GT(done, 0);
  std::printf(
      "1000 goals, 20%% loss each way, 1 attempt: %d DONE, %d TIMEOUT, %d other, %lld late "
      "confirmations\n",
      done, timeout, 1000 - done - timeout,
      static_cast<long long>(run.counters.late_confirmations));
  for (const auto& [seq, n] : run.executions_per_seq) EXPECT_EQ(n, 1) << "seq " << seq;
  for (const auto& [goal, n] : run.executions_per_goal) EXPECT_EQ(n, 1) << "goal " << goal;
}

}  // namespace
}  // namespace ephor::comm

namespace ephor::comm {
namespace {

// Catching streams refined targets: with preempt_in_flight the newest goal
// goes out as soon as the arm has accepted the one before it.
TEST(GoalRelayPreempt, ANewerGoalReplacesAnAcceptedMotionButNotOneStillBeingDelivered) {
  RelayOptions o;
  o.preempt_in_flight = true;
  o.wait_for_arm_state = false;
  GoalRelay relay(o);
  Goal first;
  first.goal_id = 1;
  first.planned_utime = 10;
  relay.submit(first, 0);
  RelayOutput out = relay.step(0);
  ASSERT_EQ(out.commands.size(), 1u);
  const int64_t seq1 = out.commands[0].seq;

  Goal second = first;
  second.goal_id = 2;
  second.planned_utime = 20;
  relay.submit(second, 1000);
  out = relay.step(1000);
  EXPECT_TRUE(out.commands.empty()) << "preempted a command the arm has not answered yet";

  relay.on_ack({seq1, 1, AckStatus::kAccepted, "", 1.0}, 2000);
  out = relay.step(2000);
  ASSERT_EQ(out.commands.size(), 1u);
  EXPECT_EQ(out.commands[0].goal.goal_id, 2);
  ASSERT_EQ(out.done.size(), 1u);
  EXPECT_EQ(out.done[0].goal_id, 1);
  EXPECT_EQ(out.done[0].status, Outcome::kFailed);
  EXPECT_NE(out.done[0].reason.find("superseded"), std::string::npos);
}

}  // namespace
}  // namespace ephor::comm
