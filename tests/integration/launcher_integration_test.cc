// ephor-launch as a user runs it: a manifest, prefixed output, a clean stop
// on duration or Ctrl-C, and a non-zero exit naming a process that fails.

#include <signal.h>

#include <gtest/gtest.h>

#include "common/time/clock.h"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

using std::chrono::seconds;

constexpr const char* kManifest = R"pb(
  name: "launch_test"
  scheduler { status_period_s: 0.5 }
  param { name: "period" default_value: "5" }
  process {
    name: "ticker"
    exec: "ephor-testtask"
    # No task-table row: the scheduler leaves the task its own period, so
    # the period in its log line is the parameter's value.
    args: [ "--task", "periodic:tick:${period}:10" ]
  }
  process {
    name: "ui"
    exec: "ephor-testtask"
    gui: true
    args: [ "--task", "periodic:draw:100" ]
  }
)pb";

std::optional<launcher::ExitInfo> exit_of(const Processes& p, const std::string& name) {
  for (const auto& e : p.exits())
    if (e.name == name) return e;
  return std::nullopt;
}

TEST(Launcher, RunsAManifestForADurationAndStopsCleanly) {
  const std::string m = write_temp_file("ok.pbtxt", kManifest);
  Processes p;
  p.start("launch", bin("ephor-launch"), {m, "--duration", "3", "--headless", "--period", "4"});
  ASSERT_TRUE(wait_until([&] { return exit_of(p, "launch").has_value(); }, seconds(30)));
  const auto e = exit_of(p, "launch");
  EXPECT_FALSE(e->signaled);
  EXPECT_EQ(e->code, 0);
  EXPECT_TRUE(p.has_line("launch", "[ticker   ]"));     // output prefixed by process name
  EXPECT_TRUE(p.has_line("launch", "period 4000 us"));  // the parameter reached the process
  EXPECT_TRUE(p.has_line("launch", "started scheduler"));
  EXPECT_FALSE(p.has_line("launch", "started ui"));  // --headless skips gui processes
  EXPECT_TRUE(p.has_line("launch", "all stopped"));
}

TEST(Launcher, CtrlCStopsEverything) {
  const std::string m = write_temp_file("int.pbtxt", kManifest);
  Processes p;
  p.start("launch", bin("ephor-launch"), {m});
  ASSERT_TRUE(wait_until([&] { return p.has_line("launch", "running; Ctrl-C"); }, seconds(10)));
  // Find the launcher's pid from its "started" lines is not needed: signal
  // the whole group through the harness by name.
  ASSERT_TRUE(wait_until([&] { return p.has_line("launch", "[ticker"); }, seconds(10)));
  p.signal("launch", SIGINT);
  ASSERT_TRUE(wait_until([&] { return exit_of(p, "launch").has_value(); }, seconds(15)));
  EXPECT_EQ(exit_of(p, "launch")->code, 0);
  EXPECT_TRUE(p.has_line("launch", "stopping on signal"));
  EXPECT_TRUE(p.has_line("launch", "all stopped"));
}

TEST(Launcher, ExitsNonZeroNamingAProcessThatDies) {
  const std::string m = write_temp_file("dies.pbtxt", R"pb(
    name: "dies"
    process {
      name: "ticker"
      exec: "ephor-testtask"
      args: [ "--task", "periodic:tick:5" ]
    }
    process {
      name: "doomed"
      exec: "ephor-testtask"
      args: [ "--task", "bogus-spec" ]
    }
  )pb");
  Processes p;
  p.start("launch", bin("ephor-launch"), {m, "--duration", "30"});
  ASSERT_TRUE(wait_until([&] { return exit_of(p, "launch").has_value(); }, seconds(20)));
  EXPECT_EQ(exit_of(p, "launch")->code, 1);
  EXPECT_TRUE(p.has_line("launch", "process doomed died unexpectedly: exited with status 1"));
  EXPECT_TRUE(
      p.has_line("launch", "bad task spec 'bogus-spec'"));  // the process's own reason, prefixed
}

TEST(Launcher, ExitsNonZeroNamingAProcessThatCannotStart) {
  const std::string m = write_temp_file("missing.pbtxt", R"pb(
    name: "missing"
    process { name: "ghost" exec: "ephor-no-such-binary" }
  )pb");
  Processes p;
  p.start("launch", bin("ephor-launch"), {m, "--duration", "5"});
  ASSERT_TRUE(wait_until([&] { return exit_of(p, "launch").has_value(); }, seconds(20)));
  EXPECT_EQ(exit_of(p, "launch")->code, 1);
  EXPECT_TRUE(p.has_line("launch", "cannot start ghost"));
}

TEST(Launcher, BadManifestAndBadOptionsAreRefusedWithReasons) {
  const std::string bad =
      write_temp_file("bad.pbtxt", "name: \"x\"\nprocess { name: \"a\" exek: \"b\" }\n");
  const std::string good = write_temp_file("good.pbtxt", kManifest);
  Processes p;
  p.start("bad", bin("ephor-launch"), {bad});
  p.start("opt", bin("ephor-launch"), {good, "--speed", "3"});
  ASSERT_TRUE(wait_until([&] { return exit_of(p, "bad") && exit_of(p, "opt"); }, seconds(20)));
  EXPECT_EQ(exit_of(p, "bad")->code, 2);
  EXPECT_TRUE(p.has_line("bad", "bad.pbtxt:2:"));
  EXPECT_EQ(exit_of(p, "opt")->code, 2);
  EXPECT_TRUE(p.has_line("opt", "unknown option --speed (parameters of"));
}

}  // namespace
}  // namespace ephor::testing
