#include "common/launch/process_group.h"

#include <signal.h>

#include <map>

#include <gtest/gtest.h>

#include "common/time/clock.h"

namespace ephor::launcher {
namespace {

struct Captured {
  std::map<std::string, std::vector<std::string>> lines;
  ProcessGroup::LineHandler handler() {
    return
        [this](const std::string& name, const std::string& line) { lines[name].push_back(line); };
  }
};

// Polls until `n` children have exited or 10 s pass.
std::vector<ExitInfo> wait_exits(ProcessGroup& g, size_t n) {
  std::vector<ExitInfo> all;
  const int64_t deadline = mono_ns() + 10'000'000'000;
  while (all.size() < n && mono_ns() < deadline) {
    auto e = g.poll(50);
    all.insert(all.end(), e.begin(), e.end());
  }
  return all;
}

ProcessSpec sh(const std::string& name, const std::string& script) {
  return {name, "/bin/sh", {"-c", script}, {}, false};
}

TEST(ProcessGroup, CapturesLinesAndExitStatus) {
  Captured cap;
  ProcessGroup g(cap.handler());
  g.start(sh("talker", "echo one; echo two >&2; printf three; exit 3"));
  const auto exits = wait_exits(g, 1);
  ASSERT_EQ(exits.size(), 1u);
  EXPECT_EQ(exits[0].code, 3);
  EXPECT_TRUE(exits[0].failure);
  EXPECT_EQ(exits[0].describe(), "exited with status 3");
  EXPECT_EQ(cap.lines["talker"], (std::vector<std::string>{"one", "two", "three"}));
}

TEST(ProcessGroup, ANulByteInOutputIsShownNotPassedOn) {
  Captured cap;
  ProcessGroup g(cap.handler());
  g.start(sh("binary", "printf 'a\\000b\\n'"));
  ASSERT_EQ(wait_exits(g, 1).size(), 1u);
  EXPECT_EQ(cap.lines["binary"], std::vector<std::string>{"a\\0b"});
}

TEST(ProcessGroup, SignalsOneChildAndForgetsExitedOnes) {
  Captured cap;
  ProcessGroup g(cap.handler());
  const pid_t a = g.start(sh("a", "exec sleep 30"));
  g.start(sh("b", "exec sleep 30"));
  EXPECT_TRUE(g.signal(a, SIGKILL));
  const auto exits = wait_exits(g, 1);
  ASSERT_EQ(exits.size(), 1u);
  EXPECT_EQ(exits[0].name, "a");
  EXPECT_EQ(exits[0].describe(), "killed by signal 9 (Killed)");
  EXPECT_EQ(g.running(), 1u);          // b untouched
  EXPECT_FALSE(g.signal(a, SIGTERM));  // no longer a child: never signals a reused pid
  g.stop_all(std::chrono::milliseconds(500));
}

TEST(ProcessGroup, AllowedCleanExitIsNotAFailure) {
  Captured cap;
  ProcessGroup g(cap.handler());
  ProcessSpec spec = sh("oneshot", "exit 0");
  spec.allow_exit = true;
  g.start(spec);
  const auto exits = wait_exits(g, 1);
  ASSERT_EQ(exits.size(), 1u);
  EXPECT_FALSE(exits[0].failure);
}

TEST(ProcessGroup, PassesEnvironment) {
  Captured cap;
  ProcessGroup g(cap.handler());
  ProcessSpec spec = sh("env", "echo $EPHOR_PROCESS");
  spec.env = {{"EPHOR_PROCESS", "vision"}};
  g.start(spec);
  wait_exits(g, 1);
  EXPECT_EQ(cap.lines["env"], std::vector<std::string>{"vision"});
}

TEST(ProcessGroup, MissingExecutableThrowsNamingTheProcess) {
  Captured cap;
  ProcessGroup g(cap.handler());
  try {
    g.start({"ghost", "/nonexistent/ephor-ghost", {}, {}, false});
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("ghost"), std::string::npos) << msg;
    EXPECT_NE(msg.find("No such file"), std::string::npos) << msg;
  }
  EXPECT_EQ(g.running(), 0u);
}

TEST(ProcessGroup, CrashIsReportedWithSignal) {
  Captured cap;
  ProcessGroup g(cap.handler());
  g.start(sh("crasher", "kill -SEGV $$"));
  const auto exits = wait_exits(g, 1);
  ASSERT_EQ(exits.size(), 1u);
  EXPECT_TRUE(exits[0].signaled);
  EXPECT_EQ(exits[0].code, SIGSEGV);
  EXPECT_TRUE(exits[0].failure);
}

TEST(ProcessGroup, StopAllTerminatesThenKillsStubbornChildren) {
  Captured cap;
  ProcessGroup g(cap.handler());
  g.start(sh("polite", "exec sleep 100"));
  g.start(sh("stubborn", "trap '' TERM; echo ready; while :; do sleep 0.05; done"));
  // Wait until the stubborn one has installed its trap.
  const int64_t deadline = mono_ns() + 10'000'000'000;
  while (cap.lines["stubborn"].empty() && mono_ns() < deadline) g.poll(20);
  const int64_t t0 = mono_ns();
  const auto exits = g.stop_all(std::chrono::milliseconds(300));
  EXPECT_EQ(g.running(), 0u);
  ASSERT_EQ(exits.size(), 2u);
  for (const auto& e : exits) {
    ASSERT_TRUE(e.signaled) << e.name;
    EXPECT_EQ(e.code, e.name == "polite" ? SIGTERM : SIGKILL) << e.name;
  }
  EXPECT_LT(mono_ns() - t0, 5'000'000'000);
}

TEST(ResolveExecutable, BinDirThenPath) {
  const std::string from_path = resolve_executable("sh", "/nonexistent");
  EXPECT_EQ(from_path.substr(from_path.size() - 3), "/sh") << from_path;
  EXPECT_EQ(resolve_executable("sh", "/bin"), "/bin/sh");
  EXPECT_EQ(resolve_executable("no-such-binary-ephor", "/bin"), "");
  EXPECT_EQ(resolve_executable("/bin/sh", ""), "/bin/sh");
}

}  // namespace
}  // namespace ephor::launcher
