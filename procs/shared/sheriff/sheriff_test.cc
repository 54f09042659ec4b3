#include "procs/shared/sheriff/sheriff.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>

#include "common/config/manifest.h"

namespace ephor::sheriff {
namespace {

constexpr int64_t kS = 1'000'000'000;

constexpr const char* kManifest = R"pb(
  name: "two_hosts"
  host { name: "planning" }
  host { name: "arm" }
  param { name: "period" default_value: "10" }
  process {
    name: "vision"
    host: "planning"
    exec: "ephor-testtask"
    args: [ "--task", "periodic:v:${period}" ]
  }
  process { name: "display" host: "planning" exec: "ephor-display" gui: true }
  process {
    name: "arm"
    host: "arm"
    exec: "ephor-testtask"
    args: [ "--task", "periodic:a:5" ]
  }
)pb";

config::Manifest manifest() { return parse_manifest(kManifest, "two_hosts.pbtxt"); }

Sheriff make(bool headless = false) {
  SheriffOptions o;
  o.params = manifest_params(manifest(), {"--period", "20"});
  o.headless = headless;
  o.lcm_url = "udpm://239.255.76.67:7700?ttl=1";
  o.id = "sheriff@test";
  return Sheriff(manifest(), o);
}

deputy_process_status_t row(const std::string& name, const std::string& state, bool run = true,
                            int32_t run_id = 0, int32_t pid = 100) {
  deputy_process_status_t r{};
  r.name = name;
  r.state = state;
  r.run = run;
  r.run_id = run_id;
  r.pid = state == "running" ? pid : 0;
  return r;
}

deputy_status_t status(const std::string& host, std::vector<deputy_process_status_t> rows) {
  deputy_status_t s{};
  s.host = host;
  s.deputy_pid = 7;
  s.processes = std::move(rows);
  s.num_processes = static_cast<int32_t>(s.processes.size());
  return s;
}

deputy_process_order_t order_of(const std::vector<deputy_orders_t>& orders,
                                const std::string& name) {
  for (const auto& o : orders)
    for (const auto& p : o.processes)
      if (p.name == name) return p;
  ADD_FAILURE() << "no order for " << name;
  return {};
}

TEST(Sheriff, FreshSystemOrdersEveryProcessToRunOnItsHost) {
  Sheriff s = make(/*headless=*/true);
  s.adopt(true);
  const auto orders = s.orders();
  ASSERT_EQ(orders.size(), 2u);
  EXPECT_EQ(orders[0].host, "planning");
  ASSERT_EQ(orders[0].num_processes, 2);
  EXPECT_EQ(orders[0].processes[0].name, "vision");
  EXPECT_EQ(orders[0].processes[0].args,
            (std::vector<std::string>{"--task", "periodic:v:20"}));  // parameter applied
  EXPECT_TRUE(orders[0].processes[0].run);
  EXPECT_FALSE(orders[0].processes[1].run);  // display is gui: stopped when headless
  EXPECT_EQ(orders[1].host, "arm");
  EXPECT_EQ(orders[1].processes[0].name, "arm");
  EXPECT_EQ(orders[1].processes[0].run_id, -1);
  EXPECT_TRUE(orders[1].start_scheduler);
  EXPECT_EQ(orders[1].lcm_url, "udpm://239.255.76.67:7700?ttl=1");
  EXPECT_NE(orders[1].manifest_text.find("two_hosts"), std::string::npos);
  // The deputy's scheduler reads a manifest that loads.
  EXPECT_NO_THROW(parse_manifest(orders[1].manifest_text, "orders"));
}

TEST(Sheriff, RestartedSheriffAdoptsTheRunningSystem) {
  Sheriff s = make();
  // A previous sheriff stopped the display and restarted vision twice.
  s.on_status(status("planning", {row("scheduler", "running"), row("vision", "running", true, 2),
                                  row("display", "stopped", false)}),
              0);
  s.on_status(status("arm", {row("scheduler", "running"), row("arm", "running")}), 0);
  s.adopt(true);
  const auto orders = s.orders();
  EXPECT_FALSE(order_of(orders, "display").run);  // kept stopped
  EXPECT_TRUE(order_of(orders, "vision").run);
  EXPECT_EQ(order_of(orders, "vision").run_id, -1);  // keep the current run: no restart
  EXPECT_TRUE(s.converged(1 * kS));
}

TEST(Sheriff, RestartAsksForTheNextRunAndWaitsForIt) {
  Sheriff s = make();
  s.on_status(status("planning", {row("scheduler", "running"), row("vision", "running", true, 3),
                                  row("display", "running")}),
              0);
  s.on_status(status("arm", {row("scheduler", "running"), row("arm", "running")}), 0);
  s.adopt(true);
  s.command(Command::kRestart, "vision");
  EXPECT_EQ(order_of(s.orders(), "vision").run_id, 4);
  std::vector<std::string> waiting;
  EXPECT_FALSE(s.converged(0, &waiting));
  ASSERT_EQ(waiting.size(), 1u);
  EXPECT_EQ(waiting[0], "vision@planning: restart pending");
  s.on_status(status("planning", {row("scheduler", "running"), row("vision", "running", true, 4),
                                  row("display", "running")}),
              1 * kS);
  s.on_status(status("arm", {row("scheduler", "running"), row("arm", "running")}), 1 * kS);
  EXPECT_TRUE(s.converged(1 * kS));
}

TEST(Sheriff, StopAllAndStartOfAFailedProcess) {
  Sheriff s = make();
  auto failed = row("arm", "failed", true, 1);
  failed.reason = "gave up after 11 crashes in a row; last exited with status 1";
  s.on_status(status("arm", {row("scheduler", "running"), failed}), 0);
  s.adopt(true);
  std::vector<std::string> waiting;
  EXPECT_FALSE(s.converged(0, &waiting));
  EXPECT_NE(std::find(waiting.begin(), waiting.end(),
                      "arm@arm: failed (gave up after 11 crashes in a row; last exited with "
                      "status 1)"),
            waiting.end());
  s.command(Command::kStart, "arm");
  EXPECT_EQ(order_of(s.orders(), "arm").run_id, 2);  // a new run revives it
  s.command(Command::kStop, "all");
  for (const auto& o : s.orders())
    for (const auto& p : o.processes) EXPECT_FALSE(p.run) << p.name;
  EXPECT_THROW(s.command(Command::kStop, "nope"), std::invalid_argument);
}

TEST(Sheriff, AVanishedDeputyIsReportedOnceAndItsReturnToo) {
  Sheriff s = make();
  s.adopt(true);
  s.on_status(status("arm", {row("arm", "running")}), 10 * kS);
  EXPECT_TRUE(s.host_events(11 * kS).empty());
  const auto lost = s.host_events(12 * kS + 600'000'000);  // 2.6 s without status
  ASSERT_EQ(lost.size(), 1u);
  EXPECT_EQ(lost[0], "host arm: deputy lost (no status for 2.6 s)");
  EXPECT_TRUE(s.host_events(13 * kS).empty());  // said once
  EXPECT_NE(s.table(13 * kS).find("DEPUTY LOST"), std::string::npos);
  std::vector<std::string> waiting;
  EXPECT_FALSE(s.converged(13 * kS, &waiting));
  s.on_status(status("arm", {row("arm", "running")}), 14 * kS);
  const auto back = s.host_events(14 * kS);
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0], "host arm: deputy back (pid 7)");
}

TEST(Sheriff, ClockOffsetPlusDelayIsTheLeastDelayedStatus) {
  Sheriff s = make();
  auto st = status("arm", {row("arm", "running")});
  st.utime = 1'000'000;
  s.on_status(st, 0, 1'000'000 + 5'000);  // 5 ms (offset + delay)
  st.utime = 2'000'000;
  s.on_status(st, 1 * kS, 2'000'000 + 3'000);  // 3 ms: the least delayed
  st.utime = 3'000'000;
  s.on_status(st, 2 * kS, 3'000'000 + 9'000);
  EXPECT_EQ(s.hosts()[1].offset_plus_delay_us, 3'000);
  EXPECT_NE(s.table(2 * kS).find("arm: deputy pid 7, load 0.00, clock offset + delay +3.0 ms"),
            std::string::npos);
}

TEST(Sheriff, OneShotOrdersSkipHostsNeverHeard) {
  Sheriff s = make();
  s.on_status(status("arm", {row("arm", "running")}), 0);
  s.adopt(false);
  s.command(Command::kStop, "arm");
  const auto orders = s.orders(/*only_heard_hosts=*/true);
  ASSERT_EQ(orders.size(), 1u);  // planning's processes are not stopped unseen
  EXPECT_EQ(orders[0].host, "arm");
}

// Found by the fuzz target sheriff_status: a deputy's row is any bytes, and
// a newline in a name broke the table into a line of its own, a name longer
// than a line lost the line's end (and the next line ran on).
TEST(Sheriff, TableShowsAnyReportedNameOnItsOwnLine) {
  Sheriff s = make();
  auto extra = row("rec\norder", "running");
  extra.reason = "a\033[2Jb";
  s.on_status(
      status("planning", {row("vision", "running"), extra, row(std::string(600, 'x'), "running")}),
      0);
  s.on_status(status("arm", {row("arm", "backoff")}), 0);
  s.adopt(true);
  const std::string table = s.table(1 * kS);
  // Header, the planning host's 5 rows (scheduler, vision, display and the
  // two extras), the arm host's 2 (scheduler, arm).
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 8) << table;
  EXPECT_NE(table.find("rec?order"), std::string::npos) << table;
  EXPECT_NE(table.find("a?[2Jb"), std::string::npos) << table;
  EXPECT_NE(table.find(std::string(37, 'x') + "..."), std::string::npos) << table;
  for (char c : table) EXPECT_TRUE(c == '\n' || static_cast<unsigned char>(c) >= 0x20);
}

// Found by the fuzz target sheriff_status: a restart after a deputy reported
// run id 2^31 - 1 overflowed the next run id (to -2^31: "any run").
TEST(Sheriff, NoNewRunPastTheLastRunId) {
  Sheriff s = make();
  s.on_status(status("arm", {row("arm", "running", true, INT32_MAX)}), 0);
  s.adopt(true);
  try {
    s.command(Command::kRestart, "all");
    FAIL() << "a restart past run id 2^31 - 1 taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'arm' on arm: its deputy reports run id 2147483647"),
              std::string::npos)
        << e.what();
  }
  for (const auto& p : s.processes()) EXPECT_EQ(p.desired_run_id, -1) << p.name;  // nothing changed
  s.command(Command::kStop, "arm");  // stopping needs no new run
  EXPECT_FALSE(s.find("arm", "arm")->desired_run);
}

TEST(Sheriff, ParametersAndNamesAreChecked) {
  EXPECT_THROW(manifest_params(manifest(), {"--nope", "1"}), std::invalid_argument);
  EXPECT_THROW(manifest_params(manifest(), {"stray"}), std::invalid_argument);
  EXPECT_THROW(manifest_params(manifest(), {"--period"}), std::invalid_argument);
  EXPECT_EQ(manifest_params(manifest(), {"--period=7"}).at("period"), "7");
  auto m = parse_manifest(R"pb(name: "x"
                               process { name: "scheduler" exec: "a" })pb",
                          "x");
  EXPECT_THROW(Sheriff(m, SheriffOptions{}), std::invalid_argument);
}

}  // namespace
}  // namespace ephor::sheriff
