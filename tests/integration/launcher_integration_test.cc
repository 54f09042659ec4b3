// ephor-launch as a user runs it: a manifest, prefixed output, a clean stop
// on duration or Ctrl-C, and a non-zero exit naming a process that fails.

#include <signal.h>

#include <cmath>
#include <fstream>
#include <map>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

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

TEST(Launcher, ReportsEachProcesssMemoryAndCatchesALeak) {
  const std::string m = write_temp_file("leak.pbtxt", R"pb(
    name: "leak"
    process {
      name: "steady"
      exec: "ephor-testtask"
      args: [ "--task", "periodic:tick:10:1000" ]
    }
    process {
      name: "leaky"
      exec: "ephor-testtask"
      args: [ "--task", "periodic:tick:10:100", "--leak-kb-per-s", "4096" ]
    }
  )pb");
  const std::string usage_path = write_temp_file("usage.json", "");
  Processes p;
  p.start("launch", bin("ephor-launch"),
          {m, "--duration", "6", "--usage", usage_path, "--usage-period-s", "0.25",
           "--usage-warmup-s", "1"});
  ASSERT_TRUE(wait_until([&] { return exit_of(p, "launch").has_value(); }, seconds(40)));
  EXPECT_EQ(exit_of(p, "launch")->code, 0);
  EXPECT_TRUE(p.has_line("launch", "memory and CPU over the run"));
  EXPECT_TRUE(p.has_line("launch", "growth MB/h"));

  std::ifstream in(usage_path);
  const auto usage = nlohmann::json::parse(in);
  std::map<std::string, nlohmann::json> by_name;
  for (const auto& row : usage.at("processes")) by_name[row.at("name")] = row;
  ASSERT_TRUE(by_name.count("steady") && by_name.count("leaky") && by_name.count("scheduler"))
      << usage.dump(2);
  // 4 MiB/s kept: 14400 MB per hour.
  const auto& leaky = by_name["leaky"];
  ASSERT_FALSE(leaky.at("rss_growth_mb_per_hour").is_null()) << leaky.dump();
  EXPECT_NEAR(leaky.at("rss_growth_mb_per_hour").get<double>(), 14400.0, 4000.0) << leaky.dump();
  EXPECT_GT(leaky.at("rss_max_mb").get<double>(), leaky.at("rss_first_mb").get<double>() + 10.0);
  const auto& steady = by_name["steady"];
  ASSERT_FALSE(steady.at("rss_growth_mb_per_hour").is_null()) << steady.dump();
  EXPECT_LT(std::abs(steady.at("rss_growth_mb_per_hour").get<double>()), 700.0) << steady.dump();
  // It burns 1 ms of CPU every 10 ms: about 0.5 s over the 5 s sampled.
  EXPECT_GT(steady.at("cpu_s").get<double>(), 0.2) << steady.dump();
  EXPECT_LT(steady.at("cpu_s").get<double>(), 2.0) << steady.dump();
}

TEST(Launcher, BadManifestAndBadOptionsAreRefusedWithReasons) {
  const std::string bad =
      write_temp_file("bad.pbtxt", "name: \"x\"\nprocess { name: \"a\" exek: \"b\" }\n");
  const std::string good = write_temp_file("good.pbtxt", kManifest);
  Processes p;
  p.start("bad", bin("ephor-launch"), {bad});
  p.start("opt", bin("ephor-launch"), {good, "--speed", "3"});
  p.start("usage", bin("ephor-launch"), {good, "--usage", "/no/such/dir/usage.json"});
  ASSERT_TRUE(wait_until(
      [&] { return exit_of(p, "bad") && exit_of(p, "opt") && exit_of(p, "usage"); }, seconds(20)));
  EXPECT_EQ(exit_of(p, "bad")->code, 2);
  EXPECT_TRUE(p.has_line("bad", "bad.pbtxt:2:"));
  EXPECT_EQ(exit_of(p, "opt")->code, 2);
  EXPECT_TRUE(p.has_line("opt", "unknown option --speed (parameters of"));
  EXPECT_EQ(exit_of(p, "usage")->code, 2);
  EXPECT_TRUE(p.has_line("usage", "--usage: cannot write /no/such/dir/usage.json"));
  EXPECT_FALSE(p.has_line("usage", "started")) << "refused before anything starts";
}

}  // namespace
}  // namespace ephor::testing
