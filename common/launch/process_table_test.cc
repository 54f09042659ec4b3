#include "common/launch/process_table.h"

#include <signal.h>

#include <gtest/gtest.h>

namespace ephor::deputy {
namespace {

constexpr int64_t kMs = 1'000'000;

ProcessOrder order(const std::string& name, bool run = true, int32_t run_id = -1) {
  ProcessOrder o;
  o.name = name;
  o.exec = "ephor-testtask";
  o.args = {"--task", "periodic:tick:10"};
  o.run = run;
  o.run_id = run_id;
  return o;
}

// Hands out pids like an executor that always manages to start.
class TableDriver {
 public:
  explicit TableDriver(RestartPolicy policy = {}) : table(policy) {}
  std::vector<Action> step(int64_t now) {
    auto actions = table.step(now);
    for (const auto& a : actions)
      if (a.kind == Action::Kind::kStart) table.started(a.name, next_pid++, now);
    return actions;
  }
  ProcessTable table;
  pid_t next_pid = 100;
};

TEST(ProcessTable, StartsOrderedProcessesInOrderAndOnlyOnce) {
  TableDriver d;
  d.table.apply({order("scheduler"), order("a"), order("b", false)}, 0);
  const auto actions = d.step(0);
  ASSERT_EQ(actions.size(), 2u);
  EXPECT_EQ(actions[0].name, "scheduler");  // the orders' sequence: the scheduler first
  EXPECT_EQ(actions[1].name, "a");
  EXPECT_EQ(d.table.find("a")->state, ProcessState::kRunning);
  EXPECT_EQ(d.table.find("b")->state, ProcessState::kStopped);
  // The same orders again (the sheriff repeats them at 1 Hz) change nothing,
  // not even the status version (no extra status message).
  const uint64_t version = d.table.version();
  d.table.apply({order("scheduler"), order("a"), order("b", false)}, 10 * kMs);
  EXPECT_TRUE(d.step(10 * kMs).empty());
  EXPECT_EQ(d.table.version(), version);
  EXPECT_EQ(d.table.find("a")->pid, 101);
}

TEST(ProcessTable, CrashRestartsWithDoublingBackoffAndKeepsTheReason) {
  RestartPolicy p;
  p.first_delay_ns = 100 * kMs;
  p.max_delay_ns = 350 * kMs;
  TableDriver d(p);
  d.table.apply({order("a")}, 0);
  d.step(0);
  int64_t t = 1000 * kMs;
  const int64_t expected_delays_ms[] = {100, 200, 350, 350};
  for (int64_t delay_ms : expected_delays_ms) {
    d.table.exited(d.table.find("a")->pid, true, SIGKILL, "killed by signal 9 (Killed)", t);
    const ProcessRow* a = d.table.find("a");
    EXPECT_EQ(a->state, ProcessState::kBackoff);
    EXPECT_EQ(a->exit_signal, SIGKILL);
    EXPECT_EQ(a->reason, "crashed: killed by signal 9 (Killed)");
    EXPECT_EQ(d.table.next_deadline_ns(), t + delay_ms * kMs);
    EXPECT_TRUE(d.step(t + delay_ms * kMs - 1).empty());
    ASSERT_EQ(d.step(t + delay_ms * kMs).size(), 1u);
    EXPECT_EQ(d.table.find("a")->state, ProcessState::kRunning);
    EXPECT_EQ(d.table.find("a")->reason, "restarted after crash: killed by signal 9 (Killed)");
    t += delay_ms * kMs + 10 * kMs;  // each run crashes after 10 ms
  }
  EXPECT_EQ(d.table.find("a")->restarts, 4);
}

TEST(ProcessTable, GivesUpAfterTheLimitUntilOrderedAnew) {
  RestartPolicy p;
  p.max_restarts = 2;
  p.first_delay_ns = 1 * kMs;
  TableDriver d(p);
  d.table.apply({order("a")}, 0);
  d.step(0);
  int64_t t = 0;
  for (int i = 0; i < 3; ++i) {
    d.table.exited(d.table.find("a")->pid, false, 3, "exited with status 3", t);
    t += 10 * kMs;
    d.step(t);
  }
  const ProcessRow* a = d.table.find("a");
  EXPECT_EQ(a->state, ProcessState::kFailed);
  EXPECT_EQ(a->exit_code, 3);
  EXPECT_EQ(a->reason, "gave up after 3 crashes in a row; last exited with status 3");
  EXPECT_TRUE(d.step(t + 60'000 * kMs).empty());  // stays down
  d.table.apply({order("a")}, t);                 // the same orders: still down
  EXPECT_TRUE(d.step(t).empty());
  d.table.apply({order("a", true, 5)}, t);  // a restart from the sheriff (new run_id)
  ASSERT_EQ(d.step(t).size(), 1u);
  EXPECT_EQ(d.table.find("a")->state, ProcessState::kRunning);
  EXPECT_EQ(d.table.find("a")->run_id, 5);
}

TEST(ProcessTable, ARunLongerThanTheStableTimeForgetsEarlierCrashes) {
  RestartPolicy p;
  p.max_restarts = 1;
  p.first_delay_ns = 1 * kMs;
  p.stable_time_ns = 1000 * kMs;
  TableDriver d(p);
  d.table.apply({order("a")}, 0);
  d.step(0);
  int64_t t = 5000 * kMs;
  for (int i = 0; i < 5; ++i) {  // crashes far apart: never gives up
    d.table.exited(d.table.find("a")->pid, true, SIGSEGV, "killed by signal 11", t);
    EXPECT_EQ(d.table.find("a")->state, ProcessState::kBackoff);
    d.step(t + 1 * kMs);
    t += 5000 * kMs;
  }
  EXPECT_EQ(d.table.find("a")->restarts, 5);
}

TEST(ProcessTable, AllowedExitIsFinishedNotRestarted) {
  TableDriver d;
  auto o = order("once");
  o.allow_exit = true;
  d.table.apply({o}, 0);
  d.step(0);
  d.table.exited(d.table.find("once")->pid, false, 0, "exited with status 0", 1 * kMs);
  EXPECT_EQ(d.table.find("once")->state, ProcessState::kFinished);
  EXPECT_TRUE(d.step(10'000 * kMs).empty());
}

TEST(ProcessTable, StopSendsSigtermThenSigkillAfterTheGrace) {
  RestartPolicy p;
  p.stop_grace_ns = 500 * kMs;
  TableDriver d(p);
  d.table.apply({order("a")}, 0);
  d.step(0);
  const pid_t pid = d.table.find("a")->pid;
  d.table.apply({order("a", false)}, 100 * kMs);
  auto actions = d.step(100 * kMs);
  ASSERT_EQ(actions.size(), 1u);
  EXPECT_EQ(actions[0].kind, Action::Kind::kSignal);
  EXPECT_EQ(actions[0].pid, pid);
  EXPECT_EQ(actions[0].signal, SIGTERM);
  EXPECT_EQ(d.table.find("a")->state, ProcessState::kStopping);
  EXPECT_TRUE(d.step(599 * kMs).empty());
  actions = d.step(600 * kMs);
  ASSERT_EQ(actions.size(), 1u);
  EXPECT_EQ(actions[0].signal, SIGKILL);
  EXPECT_TRUE(d.step(700 * kMs).empty());  // SIGKILL once
  d.table.exited(pid, true, SIGKILL, "killed by signal 9 (Killed)", 650 * kMs);
  EXPECT_EQ(d.table.find("a")->state, ProcessState::kStopped);  // not a crash: no restart
  EXPECT_EQ(d.table.find("a")->restarts, 0);
  EXPECT_TRUE(d.step(10'000 * kMs).empty());
}

TEST(ProcessTable, ProcessesLeftOutOfTheOrdersAreStoppedThenForgotten) {
  TableDriver d;
  d.table.apply({order("a"), order("b")}, 0);
  d.step(0);
  const pid_t b = d.table.find("b")->pid;
  d.table.apply({order("a")}, 1 * kMs);
  const auto actions = d.step(1 * kMs);
  ASSERT_EQ(actions.size(), 1u);
  EXPECT_EQ(actions[0].pid, b);
  EXPECT_EQ(actions[0].signal, SIGTERM);
  ASSERT_NE(d.table.find("b"), nullptr);  // still shown while it stops
  d.table.exited(b, true, SIGTERM, "killed by signal 15 (Terminated)", 2 * kMs);
  EXPECT_EQ(d.table.find("b"), nullptr);
  EXPECT_EQ(d.table.rows().size(), 1u);
}

TEST(ProcessTable, NewRunIdOrCommandRestartsOnceAndAnyRunIdKeepsTheRun) {
  TableDriver d;
  d.table.apply({order("a")}, 0);
  d.step(0);
  EXPECT_EQ(d.table.find("a")->run_id, 0);
  const pid_t first = d.table.find("a")->pid;
  // A sheriff that restarted knows no run_id and sends -1: nothing happens.
  d.table.apply({order("a", true, -1)}, 1 * kMs);
  EXPECT_TRUE(d.step(1 * kMs).empty());
  // restart: the sheriff sends the current run_id + 1.
  d.table.apply({order("a", true, 1)}, 2 * kMs);
  auto actions = d.step(2 * kMs);
  ASSERT_EQ(actions.size(), 1u);
  EXPECT_EQ(actions[0].signal, SIGTERM);
  d.table.exited(first, true, SIGTERM, "killed by signal 15 (Terminated)", 3 * kMs);
  actions = d.step(3 * kMs);
  ASSERT_EQ(actions.size(), 1u);
  EXPECT_EQ(actions[0].kind, Action::Kind::kStart);
  EXPECT_EQ(d.table.find("a")->run_id, 1);
  EXPECT_EQ(d.table.find("a")->restarts, 0);      // ordered, not a crash
  d.table.apply({order("a", true, 1)}, 4 * kMs);  // repeated: no second restart
  EXPECT_TRUE(d.step(4 * kMs).empty());
  // A changed command line restarts it too.
  auto changed = order("a", true, 1);
  changed.args.push_back("--verbose");
  d.table.apply({changed}, 5 * kMs);
  actions = d.step(5 * kMs);
  ASSERT_EQ(actions.size(), 1u);
  EXPECT_EQ(actions[0].signal, SIGTERM);
}

TEST(ProcessTable, StartFailureIsKeptAsTheReason) {
  TableDriver d;
  d.table.apply({order("a")}, 0);
  const auto actions = d.table.step(0);
  ASSERT_EQ(actions.size(), 1u);
  d.table.start_failed("a", "executable 'nope' not found");
  EXPECT_EQ(d.table.find("a")->state, ProcessState::kFailed);
  EXPECT_EQ(d.table.find("a")->reason, "executable 'nope' not found");
  EXPECT_TRUE(d.table.step(1000 * kMs).empty());
}

TEST(ProcessTable, StoppingABackoffCancelsTheRestart) {
  TableDriver d;
  d.table.apply({order("a")}, 0);
  d.step(0);
  d.table.exited(d.table.find("a")->pid, true, SIGSEGV, "killed by signal 11", 1 * kMs);
  d.table.apply({order("a", false)}, 2 * kMs);
  EXPECT_EQ(d.table.find("a")->state, ProcessState::kStopped);
  EXPECT_TRUE(d.step(100'000 * kMs).empty());
  EXPECT_EQ(d.table.next_deadline_ns(), INT64_MAX);
}

TEST(ProcessTable, DuplicateNamesInOrdersAreRefused) {
  ProcessTable t;
  EXPECT_THROW(t.apply({order("a"), order("a")}, 0), std::invalid_argument);
}

TEST(ProcessTable, UnknownPidsAreIgnored) {
  TableDriver d;
  d.table.apply({order("a")}, 0);
  d.step(0);
  d.table.exited(99999, true, SIGKILL, "killed", 1 * kMs);
  EXPECT_EQ(d.table.find("a")->state, ProcessState::kRunning);
}

}  // namespace
}  // namespace ephor::deputy
