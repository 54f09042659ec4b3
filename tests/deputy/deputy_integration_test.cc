// Deputies and sheriff as a user runs them on one network namespace: two
// deputies (hosts planning and arm), the sheriff bringing up a manifest of
// ephor-testtask processes, kill -9 of a process restarted within 1 s, start
// / stop / restart commands, a restarted sheriff that restarts nothing, a
// vanished deputy reported within 3 s, and a killed deputy whose successor
// runs every process exactly once (even one that ignores SIGTERM).

#include <dirent.h>
#include <signal.h>
#include <unistd.h>

#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>

#include <gtest/gtest.h>

#include "common/lcm/bus.h"
#include "common/runtime/channels.h"
#include "common/time/clock.h"
#include "ephor/deputy_output_t.hpp"
#include "ephor/deputy_status_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

constexpr const char* kUrl = "udpm://239.255.76.67:7713?ttl=0";

constexpr const char* kManifest = R"pb(
  name: "deputy_test"
  lcm { port: 7713 ttl: 0 }
  scheduler { status_period_s: 0.5 }
  host { name: "planning" }
  host { name: "arm" }
  process {
    name: "ticker"
    host: "planning"
    exec: "ephor-testtask"
    args: [ "--task", "periodic:dt_tick:20:100" ]
    task { name: "dt_tick" kind: PERIODIC period_ms: 20 }
  }
  process {
    name: "mover"
    host: "arm"
    exec: "ephor-testtask"
    args: [ "--task", "periodic:dt_move:10:100" ]
  }
  # Ignores SIGTERM: only SIGKILL ends it, so it outlives a killed deputy.
  process {
    name: "stubborn"
    host: "arm"
    exec: "/bin/sh"
    args: [ "-c", "trap '' TERM; exec sleep 601.5" ]
  }
)pb";

// Newest deputy_status_t per host, heard on the test's own bus.
class StatusWatch {
 public:
  StatusWatch() : bus_(kUrl, "test") {
    bus_.subscribe<deputy_status_t>(channels::kDeputyStatus, [this](const deputy_status_t& s) {
      std::lock_guard<std::mutex> lock(mutex_);
      latest_[s.host] = s;
    });
    bus_.subscribe<deputy_output_t>(channels::kDeputyOutput, [this](const deputy_output_t& o) {
      std::lock_guard<std::mutex> lock(mutex_);
      for (size_t i = 0; i < o.lines.size() && i < o.processes.size(); ++i)
        output_.push_back(o.host + "/" + o.processes[i] + ": " + o.lines[i]);
    });
    bus_.start();
  }
  ~StatusWatch() { bus_.stop(); }
  // True when a published output line "HOST/PROCESS: ..." contains `text`.
  bool output_has(const std::string& text) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& l : output_)
      if (l.find(text) != std::string::npos) return true;
    return false;
  }
  std::optional<deputy_process_status_t> process(const std::string& host, const std::string& name) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = latest_.find(host);
    if (it == latest_.end()) return std::nullopt;
    for (const auto& p : it->second.processes)
      if (p.name == name) return p;
    return std::nullopt;
  }
  int32_t deputy_pid(const std::string& host) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = latest_.find(host);
    return it == latest_.end() ? 0 : it->second.deputy_pid;
  }
  bool running(const std::string& host, const std::string& name) {
    auto p = process(host, name);
    return p && p->state == "running" && p->pid > 0;
  }

 private:
  Bus bus_;
  std::mutex mutex_;
  std::map<std::string, deputy_status_t> latest_;
  std::vector<std::string> output_;
};

// Live processes whose command line contains `marker` (this test's only);
// with `at_start`, only those whose command line starts with it.
int count_processes(const std::string& marker, bool at_start = false) {
  int n = 0;
  DIR* dir = opendir("/proc");
  while (const dirent* e = readdir(dir)) {
    if (e->d_name[0] < '0' || e->d_name[0] > '9') continue;
    std::ifstream in(std::string("/proc/") + e->d_name + "/cmdline", std::ios::binary);
    std::stringstream buf;
    buf << in.rdbuf();
    std::string cmdline = buf.str();
    for (char& c : cmdline)
      if (c == '\0') c = ' ';
    std::ifstream stat(std::string("/proc/") + e->d_name + "/stat");
    std::string pid, comm, state;
    stat >> pid >> comm >> state;
    const auto pos = cmdline.find(marker);
    if (state != "Z" && pos != std::string::npos && (!at_start || pos == 0)) ++n;
  }
  closedir(dir);
  return n;
}

std::optional<launcher::ExitInfo> exit_of(const Processes& p, const std::string& name) {
  for (const auto& e : p.exits())
    if (e.name == name) return e;
  return std::nullopt;
}

// Runs a one-shot sheriff command to its end; returns its exit status.
int sheriff(Processes& p, const std::string& name, const std::string& manifest,
            std::vector<std::string> args) {
  args.insert(args.begin(), manifest);
  p.start(name, bin("ephor-sheriff"), args, {{"LCM_DEFAULT_URL", kUrl}});
  if (!wait_until([&] { return exit_of(p, name).has_value(); }, seconds(30))) return -1;
  const auto e = exit_of(p, name);
  return e->signaled ? 128 + e->code : e->code;
}

std::vector<std::pair<std::string, std::string>> deputy_env() {
  return {{"LCM_DEFAULT_URL", kUrl}};
}

TEST(Deputy, SheriffBringsUpTwoHostsAndCrashesAreRestartedWithinOneSecond) {
  const std::string m = write_temp_file("deputy_test.pbtxt", kManifest);
  Processes p;
  StatusWatch status;
  p.start("deputy_planning", bin("ephor-deputy"), {"--host", "planning", "--grace", "0.5"},
          deputy_env());
  p.start("deputy_arm", bin("ephor-deputy"), {"--host", "arm", "--grace", "0.5"}, deputy_env());

  // Bring everything up (scripts: --wait-running exits 0 once all run).
  ASSERT_EQ(sheriff(p, "up", m, {"--wait-running", "--timeout", "20"}), 0);
  EXPECT_TRUE(p.has_line("up", "everything is running"));
  ASSERT_TRUE(status.running("planning", "scheduler"));  // each host's scheduler, first
  ASSERT_TRUE(status.running("arm", "scheduler"));
  ASSERT_TRUE(status.running("planning", "ticker"));
  ASSERT_TRUE(status.running("arm", "mover"));
  EXPECT_TRUE(p.has_line("deputy_arm", "started scheduler"));
  EXPECT_EQ(count_processes("dt_move"), 1);
  // Full status at 1 Hz: CPU and memory of each process.
  ASSERT_TRUE(
      wait_until([&] { return status.process("arm", "mover")->rss_bytes > 0; }, seconds(3)));
  // The planning host's scheduler read its task table from the manifest
  // that came with the orders.
  ASSERT_TRUE(wait_until(
      [&] { return p.has_line("deputy_planning", "scheduling 1 task(s) of host 'planning'"); },
      seconds(5)));

  // The processes' output is published, line by line, with host and process.
  EXPECT_TRUE(wait_until([&] { return status.output_has("arm/mover: "); }, seconds(5)));
  EXPECT_TRUE(status.output_has("running 1 task(s) on host arm"));

  // kill -9: restarted within 1 s, with the reason kept.
  const int32_t victim = status.process("arm", "mover")->pid;
  const int64_t killed_ns = mono_ns();
  ASSERT_EQ(kill(victim, SIGKILL), 0);
  ASSERT_TRUE(wait_until(
      [&] {
        auto s = status.process("arm", "mover");
        return s && s->state == "running" && s->pid != victim;
      },
      seconds(5)));
  const double restart_s = static_cast<double>(mono_ns() - killed_ns) * 1e-9;
  std::fprintf(stderr, "kill -9 to running again (seen in status): %.3f s\n", restart_s);
  EXPECT_LT(restart_s, 1.0);
  const auto mover = status.process("arm", "mover");
  EXPECT_EQ(mover->restarts, 1);
  EXPECT_EQ(mover->exit_signal, SIGKILL);
  EXPECT_EQ(mover->reason, "restarted after crash: killed by signal 9 (Killed)");
  EXPECT_EQ(count_processes("dt_move"), 1);

  // A sheriff that starts while all runs restarts nothing.
  const int32_t ticker = status.process("planning", "ticker")->pid;
  const int32_t mover_pid = status.process("arm", "mover")->pid;
  ASSERT_EQ(sheriff(p, "again", m, {"--wait-running", "--timeout", "10"}), 0);
  EXPECT_EQ(status.process("planning", "ticker")->pid, ticker);
  EXPECT_EQ(status.process("arm", "mover")->pid, mover_pid);

  // stop / start / restart one process.
  ASSERT_EQ(sheriff(p, "stop", m, {"stop", "mover"}), 0);
  EXPECT_EQ(status.process("arm", "mover")->state, "stopped");
  EXPECT_EQ(count_processes("dt_move"), 0);
  EXPECT_TRUE(status.running("planning", "ticker"));  // the others untouched
  ASSERT_EQ(sheriff(p, "start", m, {"start", "mover"}), 0);
  EXPECT_TRUE(status.running("arm", "mover"));
  ASSERT_EQ(sheriff(p, "restart", m, {"restart", "ticker"}), 0);
  EXPECT_NE(status.process("planning", "ticker")->pid, ticker);
  EXPECT_EQ(status.process("planning", "ticker")->restarts, 0);  // ordered, not a crash
  EXPECT_EQ(count_processes("dt_tick"), 1);
  EXPECT_EQ(sheriff(p, "bad", m, {"stop", "nope"}), 2);
  EXPECT_TRUE(p.has_line("bad", "no process 'nope' in the manifest"));
}

TEST(Deputy, VanishedDeputyIsReportedAndItsSuccessorRunsEachProcessOnce) {
  const std::string m = write_temp_file("deputy_test2.pbtxt", kManifest);
  Processes p;
  StatusWatch status;
  p.start("deputy_planning", bin("ephor-deputy"), {"--host", "planning", "--grace", "0.5"},
          deputy_env());
  p.start("deputy_arm", bin("ephor-deputy"), {"--host", "arm", "--grace", "0.5"}, deputy_env());
  // The live sheriff: keeps sending orders and shows the table.
  p.start("sheriff", bin("ephor-sheriff"), {m}, {{"LCM_DEFAULT_URL", kUrl}});
  ASSERT_TRUE(wait_until(
      [&] {
        return status.running("arm", "mover") && status.running("arm", "stubborn") &&
               status.running("planning", "ticker");
      },
      seconds(20)));
  // Once the shell has set its trap and become "sleep 601.5".
  ASSERT_TRUE(wait_until([&] { return count_processes("sleep 601.5", true) == 1; }, seconds(5)));

  // The arm host's deputy dies (kill -9): its processes get SIGTERM from the
  // kernel (PR_SET_PDEATHSIG); "stubborn" ignores it and lives on.
  const int32_t dead_deputy = status.deputy_pid("arm");
  const int64_t killed_ns = mono_ns();
  p.signal("deputy_arm", SIGKILL);
  ASSERT_TRUE(
      wait_until([&] { return p.has_line("sheriff", "host arm: deputy lost"); }, seconds(5)));
  const double report_s = static_cast<double>(mono_ns() - killed_ns) * 1e-9;
  std::fprintf(stderr, "deputy killed to sheriff report: %.3f s\n", report_s);
  EXPECT_LT(report_s, 3.0);
  EXPECT_TRUE(wait_until([&] { return count_processes("dt_move") == 0; }, seconds(5)));
  EXPECT_EQ(count_processes("sleep 601.5", true), 1);

  // A new deputy for the host: stops the leftover, then runs each process once.
  p.start("deputy_arm2", bin("ephor-deputy"), {"--host", "arm", "--grace", "0.5"}, deputy_env());
  ASSERT_TRUE(wait_until(
      [&] {
        return status.deputy_pid("arm") != dead_deputy && status.running("arm", "mover") &&
               status.running("arm", "stubborn");
      },
      seconds(15)));
  EXPECT_TRUE(p.has_line("deputy_arm2", "a previous deputy left running"));
  EXPECT_TRUE(
      wait_until([&] { return p.has_line("sheriff", "host arm: deputy back"); }, seconds(5)));
  EXPECT_EQ(count_processes("dt_move"), 1);
  // The new shell (or, once it exec'd, its sleep: the same process); the
  // leftover is gone.
  EXPECT_EQ(count_processes("sleep 601.5"), 1);
  EXPECT_EQ(count_processes("dt_tick"), 1);  // the other host was never disturbed
  EXPECT_EQ(status.process("planning", "ticker")->restarts, 0);

  // Leaving the live sheriff leaves the system running; then stop all. The
  // stubborn process needs SIGKILL after the grace time.
  p.signal("sheriff", SIGTERM);
  ASSERT_TRUE(wait_until([&] { return exit_of(p, "sheriff").has_value(); }, seconds(5)));
  EXPECT_EQ(count_processes("dt_move"), 1);
  ASSERT_EQ(sheriff(p, "stop_all", m, {"stop", "all"}), 0);
  EXPECT_EQ(count_processes("dt_move"), 0);
  EXPECT_EQ(count_processes("dt_tick"), 0);
  EXPECT_EQ(count_processes("sleep 601.5", true), 0);
  EXPECT_EQ(status.process("arm", "stubborn")->reason, "stopped: killed by signal 9 (Killed)");
}

}  // namespace
}  // namespace ephor::testing
