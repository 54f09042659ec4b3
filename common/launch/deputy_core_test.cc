#include "common/launch/deputy_core.h"

#include <signal.h>

#include <functional>
#include <map>

#include <gtest/gtest.h>

#include "common/time/clock.h"

namespace ephor::deputy {
namespace {

constexpr int64_t kMs = 1'000'000;

ProcessOrder sh(const std::string& name, const std::string& script) {
  ProcessOrder o;
  o.name = name;
  o.exec = "/bin/sh";
  o.args = {"-c", script};
  return o;
}

// A core whose output lines and events the test keeps.
struct Harness {
  explicit Harness(RestartPolicy policy)
      : core(policy, "/nonexistent", [this](const std::string& name, const std::string& line) {
          lines[name].push_back(line);
        }) {}

  // Polls until `done` holds or 10 s pass; never a bare sleep.
  bool poll_until(const std::function<bool()>& done) {
    const int64_t deadline = mono_ns() + 10'000 * kMs;
    while (!done()) {
      if (mono_ns() >= deadline) return false;
      for (auto& e : core.poll(20)) events.push_back(std::move(e));
    }
    return true;
  }
  std::vector<DeputyEvent> of(DeputyEvent::Kind kind, const std::string& name) const {
    std::vector<DeputyEvent> out;
    for (const auto& e : events)
      if (e.kind == kind && e.name == name) out.push_back(e);
    return out;
  }
  ProcessState state(const std::string& name) const { return core.table().find(name)->state; }

  std::map<std::string, std::vector<std::string>> lines;
  std::vector<DeputyEvent> events;
  DeputyCore core;  // last: destroyed (its children stopped) before what its handler writes to
};

RestartPolicy quick_policy() {
  RestartPolicy p;
  p.first_delay_ns = 20 * kMs;
  p.max_delay_ns = 50 * kMs;
  p.max_restarts = 3;
  p.stop_grace_ns = 300 * kMs;
  return p;
}

TEST(DeputyCore, StartsInTheOrdersSequenceWithTheirEnvironment) {
  Harness h(quick_policy());
  ProcessOrder scheduler = sh("scheduler", "echo \"$EPHOR_PROCESS up\"; exec sleep 30");
  scheduler.env = {{"EPHOR_PROCESS", "scheduler"}};
  h.core.apply({scheduler, sh("a", "echo a up; exec sleep 30"), sh("b", "exec sleep 30")});
  // One poll starts everything: no wait between the orders and the starts.
  h.events = h.core.poll(0);
  ASSERT_EQ(h.events.size(), 3u);
  EXPECT_EQ(h.events[0].name, "scheduler");  // the host's scheduler comes first in the orders
  EXPECT_EQ(h.events[1].name, "a");
  EXPECT_EQ(h.events[2].name, "b");
  for (const auto& e : h.events) {
    EXPECT_EQ(e.kind, DeputyEvent::Kind::kStarted) << e.name;
    EXPECT_EQ(e.path, "/bin/sh");
    EXPECT_EQ(e.state, ProcessState::kRunning);
    EXPECT_GT(e.pid, 0);
  }
  EXPECT_LE(h.events[0].at_ns, h.events[1].at_ns);
  ASSERT_TRUE(h.poll_until([&] { return !h.lines["scheduler"].empty() && !h.lines["a"].empty(); }));
  EXPECT_EQ(h.lines["scheduler"], std::vector<std::string>{"scheduler up"});
  EXPECT_EQ(h.core.table().find("b")->pid, h.events[2].pid);
}

TEST(DeputyCore, RestartsACrashingChildWithBackoffUpToTheLimit) {
  Harness h(quick_policy());
  h.core.apply({sh("crasher", "echo run; exit 3")});
  ASSERT_TRUE(h.poll_until([&] { return h.state("crasher") == ProcessState::kFailed; }));
  const auto starts = h.of(DeputyEvent::Kind::kStarted, "crasher");
  const auto exits = h.of(DeputyEvent::Kind::kExited, "crasher");
  ASSERT_EQ(starts.size(), 4u);  // the first run and max_restarts = 3 restarts
  ASSERT_EQ(exits.size(), 4u);
  for (size_t i = 0; i < exits.size(); ++i) {
    EXPECT_EQ(exits[i].exit.describe(), "exited with status 3");
    EXPECT_EQ(exits[i].state,
              i + 1 < exits.size() ? ProcessState::kBackoff : ProcessState::kFailed);
  }
  // Each restart waited its backoff, doubling from 20 ms up to the 50 ms cap.
  const int64_t want_ms[] = {20, 40, 50};
  for (size_t i = 0; i < 3; ++i)
    EXPECT_GE(starts[i + 1].at_ns - exits[i].at_ns, want_ms[i] * kMs) << "restart " << i + 1;
  EXPECT_EQ(exits.back().reason, "gave up after 4 crashes in a row; last exited with status 3");
  EXPECT_EQ(h.core.table().find("crasher")->restarts, 3);
  EXPECT_EQ(h.lines["crasher"].size(), 4u);
  // Failed stays down: no start however long it is polled.
  h.events.clear();
  for (int i = 0; i < 5; ++i)
    for (auto& e : h.core.poll(20)) h.events.push_back(std::move(e));
  EXPECT_TRUE(h.events.empty());
}

TEST(DeputyCore, WithoutRestartsADeathIsReportedWithTheProcessName) {
  RestartPolicy p = quick_policy();
  p.max_restarts = 0;  // ephor-launch's `run`
  Harness h(p);
  h.core.apply({sh("steady", "exec sleep 30"), sh("doomed", "echo 'bad spec' >&2; exit 1")});
  DeputyEvent death;
  ASSERT_TRUE(h.poll_until([&] {
    for (const auto& e : h.events)
      if (e.kind == DeputyEvent::Kind::kExited && e.state == ProcessState::kFailed) {
        death = e;
        return true;
      }
    return false;
  }));
  EXPECT_EQ(death.name, "doomed");
  EXPECT_EQ(death.exit.describe(), "exited with status 1");
  EXPECT_EQ(death.reason, "gave up after 1 crashes in a row; last exited with status 1");
  EXPECT_EQ(h.lines["doomed"], std::vector<std::string>{"bad spec"});  // its own reason, captured
  EXPECT_EQ(h.of(DeputyEvent::Kind::kStarted, "doomed").size(), 1u);
  EXPECT_EQ(h.state("steady"), ProcessState::kRunning);  // what to do about it is the caller's
}

TEST(DeputyCore, AllowedExitFinishesAndAMissingExecutableFails) {
  Harness h(quick_policy());
  ProcessOrder once = sh("once", "exit 0");
  once.allow_exit = true;
  ProcessOrder ghost;
  ghost.name = "ghost";
  ghost.exec = "ephor-no-such-binary";
  h.core.apply({once, ghost});
  ASSERT_TRUE(h.poll_until([&] { return h.state("once") == ProcessState::kFinished; }));
  const auto failed = h.of(DeputyEvent::Kind::kStartFailed, "ghost");
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_EQ(failed[0].state, ProcessState::kFailed);
  EXPECT_EQ(failed[0].reason,
            "executable 'ephor-no-such-binary' not found in /nonexistent or $PATH");
}

TEST(DeputyCore, StopAllSignalsNewestFirstThenKillsTheStubbornAfterTheGrace) {
  Harness h(quick_policy());
  h.core.apply({sh("logger", "exec sleep 30"),
                sh("stubborn", "trap '' TERM; echo ready; while :; do sleep 0.05; done"),
                sh("polite", "exec sleep 30")});
  // Wait until the stubborn one has installed its trap.
  ASSERT_TRUE(h.poll_until([&] { return !h.lines["stubborn"].empty(); }));
  const int64_t t0 = mono_ns();
  const auto events = h.core.stop_all();
  std::vector<std::pair<std::string, int>> signals;
  for (const auto& e : events)
    if (e.kind == DeputyEvent::Kind::kSignalled) signals.emplace_back(e.name, e.signal);
  const std::vector<std::pair<std::string, int>> want = {
      {"polite", SIGTERM}, {"stubborn", SIGTERM}, {"logger", SIGTERM}, {"stubborn", SIGKILL}};
  EXPECT_EQ(signals, want);
  for (const auto& row : h.core.table().rows()) {
    EXPECT_EQ(row.state, ProcessState::kStopped) << row.order.name;
    EXPECT_EQ(row.pid, 0) << row.order.name;
    EXPECT_EQ(row.exit_signal, row.order.name == "stubborn" ? SIGKILL : SIGTERM) << row.order.name;
  }
  EXPECT_GE(mono_ns() - t0, 300 * kMs);  // SIGKILL only after the grace time
  EXPECT_LT(mono_ns() - t0, 5'000 * kMs);
  // Stopped for good: polling starts nothing.
  EXPECT_TRUE(h.core.poll(0).empty());
}

TEST(DeputyCore, NewestFirstCountsRestarts) {
  // A process restarted after a crash is the newest: it is stopped first.
  Harness h(quick_policy());
  h.core.apply({sh("first", "exec sleep 30"), sh("second", "exec sleep 30")});
  ASSERT_TRUE(h.poll_until([&] { return h.state("second") == ProcessState::kRunning; }));
  const pid_t old = h.core.table().find("first")->pid;
  ASSERT_EQ(kill(old, SIGKILL), 0);
  ASSERT_TRUE(h.poll_until([&] {
    const ProcessRow* r = h.core.table().find("first");
    return r->state == ProcessState::kRunning && r->pid != old;
  }));
  std::vector<std::string> order;
  for (const auto& e : h.core.stop_all())
    if (e.kind == DeputyEvent::Kind::kSignalled) order.push_back(e.name);
  EXPECT_EQ(order, (std::vector<std::string>{"first", "second"}));
}

}  // namespace
}  // namespace ephor::deputy
