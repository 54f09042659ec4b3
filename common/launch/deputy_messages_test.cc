#include "common/launch/deputy_messages.h"

#include <gtest/gtest.h>

namespace ephor::deputy {
namespace {

DeputySettings settings() {
  return {"arm", "/opt/ephor/bin", "udpm://239.255.76.67:7667?ttl=0", "/tmp/d/manifest.pbtxt"};
}

deputy_process_order_t process(const std::string& name, bool run = true) {
  deputy_process_order_t p{};
  p.name = name;
  p.exec = "ephor-arm";
  p.args = {"--x=1"};
  p.num_args = 1;
  p.run = run;
  p.run_id = -1;
  return p;
}

deputy_orders_t orders(std::vector<deputy_process_order_t> ps, bool scheduler = true) {
  deputy_orders_t o{};
  o.host = "arm";
  o.manifest_text = "name: \"m\"";
  o.lcm_url = "udpm://239.255.76.67:7700?ttl=1";
  o.start_scheduler = scheduler;
  o.processes = std::move(ps);
  o.num_processes = static_cast<int32_t>(o.processes.size());
  return o;
}

std::string env(const ProcessOrder& o, const std::string& name) {
  for (const auto& [k, v] : o.env)
    if (k == name) return v;
  return "<unset>";
}

TEST(DeputyMessages, SchedulerFirstThenProcessesWithTheirEnvironment) {
  const auto out = host_orders(orders({process("arm"), process("spare", false)}), settings());
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].name, "scheduler");
  EXPECT_EQ(out[0].exec, "ephor-scheduler");
  EXPECT_EQ(out[0].args,
            (std::vector<std::string>{"--manifest", "/tmp/d/manifest.pbtxt", "--host", "arm"}));
  EXPECT_EQ(out[1].name, "arm");
  EXPECT_EQ(out[1].args, std::vector<std::string>{"--x=1"});
  EXPECT_FALSE(out[2].run);
  // The orders' URL (the manifest's TTL) reaches the processes.
  EXPECT_EQ(env(out[1], "LCM_DEFAULT_URL"), "udpm://239.255.76.67:7700?ttl=1");
  EXPECT_EQ(env(out[1], "EPHOR_PROCESS"), "arm");
  EXPECT_EQ(env(out[1], "EPHOR_HOST"), "arm");
  EXPECT_EQ(env(out[1], "EPHOR_DEPUTY"), "arm@udpm://239.255.76.67:7667?ttl=0");
}

TEST(DeputyMessages, ANewManifestRestartsOnlyTheScheduler) {
  auto a = orders({process("arm")});
  auto b = a;
  b.manifest_text += "\n# changed";
  const auto oa = host_orders(a, settings());
  const auto ob = host_orders(b, settings());
  EXPECT_FALSE(oa[0].same_command(ob[0]));
  EXPECT_TRUE(oa[1].same_command(ob[1]));
}

TEST(DeputyMessages, MalformedOrdersAreRefusedWithTheReason) {
  auto expect_refused = [](const deputy_orders_t& o, const std::string& what) {
    try {
      host_orders(o, settings());
      ADD_FAILURE() << "accepted: " << what;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  auto other_host = orders({process("arm")});
  other_host.host = "planning";
  expect_refused(other_host, "orders for host 'planning'");
  auto bad_count = orders({process("arm")});
  bad_count.num_processes = 3;
  expect_refused(bad_count, "num_processes 3 but 1");
  expect_refused(orders({process("arm"), process("arm")}), "'arm' twice");
  expect_refused(orders({process("scheduler")}), "clashes");
  auto no_exec = process("x");
  no_exec.exec.clear();
  expect_refused(orders({no_exec}), "'x' has no exec");
  auto bad_args = process("x");
  bad_args.num_args = 5;
  expect_refused(orders({bad_args}), "num_args");
  auto no_manifest = orders({process("arm")});
  no_manifest.manifest_text.clear();
  expect_refused(no_manifest, "no manifest");
  // Strings with a NUL byte inside (found by fuzz_deputy_orders: the name
  // went into the status, which LCM then encoded short).
  auto nul_name = process(std::string("ar\0m", 4));
  expect_refused(orders({nul_name}), "a process name contains a NUL byte");
  auto nul_arg = process("x");
  nul_arg.args = {std::string("--a\0b", 5)};
  expect_refused(orders({nul_arg}), "process 'x': an argument contains a NUL byte");
  auto nul_sheriff = orders({process("arm")});
  nul_sheriff.sheriff = std::string("s\0", 2);
  expect_refused(nul_sheriff, "the sheriff's name contains a NUL byte");
  // Without the scheduler, no manifest is needed and the name is free.
  auto plain = orders({process("scheduler")}, false);
  plain.manifest_text.clear();
  EXPECT_EQ(host_orders(plain, settings()).size(), 1u);
}

TEST(DeputyMessages, StatusCarriesEveryRow) {
  ProcessTable table;
  table.apply(host_orders(orders({process("arm")}), settings()), 0);
  for (const auto& a : table.step(0))
    if (a.kind == Action::Kind::kStart) table.started(a.name, a.name == "arm" ? 42 : 41, 0);
  std::map<pid_t, UsageSample> usage{{42, {12.5f, 4096}}};
  const auto s = make_status(table, usage, settings(), 777, "sheriff@x", 2'000'000'000);
  EXPECT_EQ(s.host, "arm");
  EXPECT_EQ(s.orders_utime, 777);
  ASSERT_EQ(s.num_processes, 2);
  EXPECT_EQ(s.processes[1].name, "arm");
  EXPECT_EQ(s.processes[1].state, "running");
  EXPECT_EQ(s.processes[1].pid, 42);
  EXPECT_FLOAT_EQ(s.processes[1].cpu_percent, 12.5f);
  EXPECT_EQ(s.processes[1].rss_bytes, 4096);
  EXPECT_EQ(s.processes[1].uptime_us, 2'000'000);
  EXPECT_EQ(s.processes[1].run_id, 0);
}

}  // namespace
}  // namespace ephor::deputy
