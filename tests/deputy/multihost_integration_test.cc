// The two-machine procedure of procs/shared/deputy/README.md, with machines made of
// network namespaces: hosts "planning" and "arm" each in a namespace of its
// own (tests/deputy/host-netns), joined by veth pairs to a bridge in the
// test's namespace, where the sheriff runs (the "anywhere" machine). LCM
// crosses between them only with ttl=1, as on a real LAN.

#include <signal.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <regex>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/runtime/channels.h"
#include "common/time/clock.h"
#include "ephor/arm_ack_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/deputy_status_t.hpp"
#include "ephor/shepherd_ground_truth_t.hpp"
#include "ephor/shepherd_objects_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

using std::chrono::seconds;

// Newest deputy_status_t per host and counts of other channels.
class Watch {
 public:
  explicit Watch(const std::string& url) : bus_(url, "test") {
    bus_.subscribe<deputy_status_t>(channels::kDeputyStatus, [this](const deputy_status_t& s) {
      std::lock_guard<std::mutex> lock(mutex_);
      latest_[s.host] = s;
    });
    bus_.subscribe<arm_state_t>("ARM_STATE", [this](const arm_state_t&) {
      std::lock_guard<std::mutex> lock(mutex_);
      ++arm_states_;
    });
    bus_.subscribe<shepherd_objects_t>("OBJECTS", [this](const shepherd_objects_t& o) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (o.num_objects > 0) ++tracked_;
    });
    bus_.subscribe<shepherd_ground_truth_t>(channels::kGroundTruth,
                                            [this](const shepherd_ground_truth_t& t) {
                                              std::lock_guard<std::mutex> lock(mutex_);
                                              herd_ = {t.sim_time_s, t.escapes, t.saves};
                                            });
    bus_.subscribe<arm_ack_t>("ARM_ACK", [this](const arm_ack_t& a) {
      std::lock_guard<std::mutex> lock(mutex_);
      ++arm_acks_;
      acked_seqs_.insert(a.seq);
    });
    bus_.start();
  }
  ~Watch() { bus_.stop(); }
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
  int64_t arm_states() {
    std::lock_guard<std::mutex> lock(mutex_);
    return arm_states_;
  }
  // OBJECTS messages with at least one tracked object.
  int64_t tracked() {
    std::lock_guard<std::mutex> lock(mutex_);
    return tracked_;
  }
  // Distinct commands (ARM_CMD seq) the arm answered.
  size_t commands_acked() {
    std::lock_guard<std::mutex> lock(mutex_);
    return acked_seqs_.size();
  }
  int64_t arm_acks() {
    std::lock_guard<std::mutex> lock(mutex_);
    return arm_acks_;
  }
  // The simulator's newest ground truth: simulated time (s), escapes and saves.
  struct Herd {
    double sim_time_s = 0.0;
    int32_t escapes = 0;
    int32_t saves = 0;
  };
  Herd herd() {
    std::lock_guard<std::mutex> lock(mutex_);
    return herd_;
  }

 private:
  Bus bus_;
  std::mutex mutex_;
  std::map<std::string, deputy_status_t> latest_;
  int64_t arm_states_ = 0;
  int64_t arm_acks_ = 0;
  int64_t tracked_ = 0;
  Herd herd_;
  std::set<int64_t> acked_seqs_;
};

void run(const std::string& command) { ASSERT_EQ(std::system(command.c_str()), 0) << command; }

// The LAN: bridge br0 in the test's namespace (10.77.0.1), multicast routed
// onto it. Machines join it with tests/deputy/host-netns.
class Lan : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    run("ip link add br0 type bridge mcast_snooping 0 && ip link set br0 up && "
        "ip addr add 10.77.0.1/24 dev br0 && ip route replace 224.0.0.0/4 dev br0");
  }
  // Starts `args` on machine `name` (a new namespace at `address`).
  static void start_on(Processes& p, const std::string& label, const std::string& name,
                       const std::string& address, std::vector<std::string> args) {
    args.insert(args.begin(), {"br0", name, address});
    p.start(label, source_path("tests/deputy/host-netns"), args);
  }
  // The README's steps 1 and 2: machines "planning" and "arm" (namespaces
  // planning<n> at 10.77.0.<10(n-1)+2> and arm<n> at the next address), a
  // deputy on each (labels deputy_planning, deputy_arm), `extra` appended
  // to both deputies' command lines.
  static void start_two_machines(Processes& p, int n, const std::string& url,
                                 const std::vector<std::string>& extra = {}) {
    const int a = 10 * (n - 1) + 2;
    for (const auto& [host, address] :
         {std::pair{std::string("planning"), a}, std::pair{std::string("arm"), a + 1}}) {
      std::vector<std::string> args = {bin("ephor-deputy"), "--host", host, "--lcm-url", url};
      args.insert(args.end(), extra.begin(), extra.end());
      start_on(p, "deputy_" + host, host + std::to_string(n), "10.77.0." + std::to_string(address),
               args);
    }
  }
};

std::optional<launcher::ExitInfo> exit_of(const Processes& p, const std::string& name) {
  for (const auto& e : p.exits())
    if (e.name == name) return e;
  return std::nullopt;
}

int run_to_end(Processes& p, const std::string& name, const std::vector<std::string>& args,
               int timeout_s = 60) {
  p.start(name, bin("ephor-sheriff"), args);
  if (!wait_until([&] { return exit_of(p, name).has_value(); }, seconds(timeout_s))) return -1;
  const auto e = exit_of(p, name);
  return e->signaled ? 128 + e->code : e->code;
}

constexpr const char* kSmall = R"pb(
  name: "lan_test"
  lcm { port: 7716 ttl: TTL }
  host { name: "planning" }
  host { name: "arm" }
  process {
    name: "ticker"
    host: "planning"
    exec: "ephor-testtask"
    args: [ "--task", "periodic:lan_tick:20" ]
  }
  process {
    name: "mover"
    host: "arm"
    exec: "ephor-testtask"
    args: [ "--task", "periodic:lan_move:10" ]
  }
)pb";

std::string small_manifest(int ttl) {
  return std::regex_replace(kSmall, std::regex("TTL"), std::to_string(ttl));
}

TEST_F(Lan, TtlZeroStaysOnTheMachine) {
  // Deputies on ttl=0 are heard on their own machine only: the sheriff on
  // the other side of the bridge hears none and says so.
  const std::string url = "udpm://239.255.76.67:7716?ttl=0";
  const std::string m = write_temp_file("lan0.pbtxt", small_manifest(0));
  Processes p;
  start_on(p, "deputy_arm", "arm0", "10.77.0.13",
           {bin("ephor-deputy"), "--host", "arm", "--lcm-url", url});
  ASSERT_TRUE(
      wait_until([&] { return p.has_line("deputy_arm", "waiting for orders"); }, seconds(10)));
  EXPECT_EQ(run_to_end(p, "sheriff", {m, "--wait-running", "--timeout", "3"}), 1);
  EXPECT_TRUE(p.has_line("sheriff", "host arm: no deputy heard yet"));
  EXPECT_FALSE(p.has_line("deputy_arm", "started"));
}

TEST_F(Lan, TwoMachinesRunTheManifestAndSurviveAKilledDeputy) {
  const std::string url = "udpm://239.255.76.67:7716?ttl=1";
  const std::string m = write_temp_file("lan1.pbtxt", small_manifest(1));
  Processes p;
  Watch watch(url);
  // README step 1 and 2: a deputy on each machine.
  start_two_machines(p, 1, url, {"--grace", "0.5"});
  // README step 3: the sheriff anywhere; the URL comes from the manifest.
  ASSERT_EQ(run_to_end(p, "up", {m, "--wait-running", "--timeout", "20"}), 0);
  EXPECT_TRUE(p.has_line("up", "LCM udpm://239.255.76.67:7716?ttl=1"));
  EXPECT_TRUE(watch.running("arm", "mover"));
  EXPECT_TRUE(watch.running("planning", "ticker"));

  // kill -9 on the arm machine: restarted within 1 s.
  const int32_t victim = watch.process("arm", "mover")->pid;
  const int64_t t0 = mono_ns();
  ASSERT_EQ(kill(victim, SIGKILL), 0);
  ASSERT_TRUE(wait_until(
      [&] {
        auto s = watch.process("arm", "mover");
        return s && s->state == "running" && s->pid != victim;
      },
      seconds(5)));
  const double restart_s = static_cast<double>(mono_ns() - t0) * 1e-9;
  std::fprintf(stderr, "across the LAN: kill -9 to running again: %.3f s\n", restart_s);
  EXPECT_LT(restart_s, 1.0);

  // The arm machine's deputy dies: the live sheriff reports it within 3 s.
  p.start("sheriff", bin("ephor-sheriff"), {m});
  ASSERT_TRUE(wait_until([&] { return p.has_line("sheriff", "PROCESS"); }, seconds(10)));
  const int32_t dead = watch.deputy_pid("arm");
  const int64_t t1 = mono_ns();
  ASSERT_EQ(kill(dead, SIGKILL), 0);
  ASSERT_TRUE(
      wait_until([&] { return p.has_line("sheriff", "host arm: deputy lost"); }, seconds(5)));
  const double lost_s = static_cast<double>(mono_ns() - t1) * 1e-9;
  std::fprintf(stderr, "across the LAN: deputy killed to sheriff report: %.3f s\n", lost_s);
  EXPECT_LT(lost_s, 3.0);

  // The machine comes back (a new deputy): the sheriff's orders bring its
  // process back, once.
  start_on(p, "deputy_arm2", "arm2", "10.77.0.4",
           {bin("ephor-deputy"), "--host", "arm", "--lcm-url", url, "--grace", "0.5"});
  ASSERT_TRUE(
      wait_until([&] { return watch.deputy_pid("arm") != dead && watch.running("arm", "mover"); },
                 seconds(15)));
  EXPECT_TRUE(
      wait_until([&] { return p.has_line("sheriff", "host arm: deputy back"); }, seconds(5)));
  EXPECT_EQ(watch.process("planning", "ticker")->restarts, 0);
}

// deploy/shepherd.pbtxt with its lcm line set to ttl: 1 (the README's LAN
// set-up), written to a temporary file of that name; returns its path.
std::string lan_shepherd_manifest(const std::string& name) {
  std::ifstream in(source_path("deploy/shepherd.pbtxt"));
  std::stringstream text;
  text << in.rdbuf();
  const std::string lan = std::regex_replace(text.str(), std::regex("ttl: 0"), "ttl: 1");
  EXPECT_NE(lan.find("ttl: 1"), std::string::npos) << "no lcm ttl in deploy/shepherd.pbtxt";
  return write_temp_file(name, lan);
}

// The shepherd manifest's LCM URL once its ttl is 1.
constexpr const char* kShepherdLanUrl = "udpm://239.255.76.67:7667?ttl=1";

// The README's step 5: the sheriff brings manifest m up (headless, seed 7,
// plus `extra`, e.g. the sheep) and exits when everything runs; its exit code.
int shepherd_up(Processes& p, const std::string& m, std::vector<std::string> extra) {
  std::vector<std::string> args = {m,        "--headless", "--wait-running", "--timeout", "40",
                                   "--seed", "7"};
  args.insert(args.end(), extra.begin(), extra.end());
  return run_to_end(p, "up", args);
}

// deploy/shepherd.pbtxt as the README runs it on two machines: the manifest's
// lcm line set to ttl: 1, the arm on the "arm" machine, the rest on
// "planning", the sheriff on a third.
TEST_F(Lan, ShepherdAcrossTwoMachines) {
  const std::string m = lan_shepherd_manifest("shepherd_lan.pbtxt");
  const std::string summary = write_temp_file("shepherd_lan_summary.json", "");
  const std::string url = kShepherdLanUrl;
  Processes p;
  Watch watch(url);
  start_two_machines(p, 3, url, {"--quiet"});
  ASSERT_EQ(shepherd_up(p, m, {"--sheep", "1", "--summary", summary}), 0);
  // The arm (on its machine) publishes ARM_STATE; it reaches this one.
  ASSERT_TRUE(wait_until([&] { return watch.arm_states() > 100; }, seconds(10)));

  // kill -9 of every process in turn (the monitor first, so its summary
  // covers the rest): each restarted within 1 s, and the system goes on: the
  // arm's state and tracked objects flow again before the next kill.
  const std::vector<std::pair<std::string, std::string>> victims = {
      {"planning", "monitor"},    {"arm", "arm"},
      {"planning", "sim"},        {"planning", "vision"},
      {"planning", "worldmodel"}, {"planning", "planner"},
      {"planning", "comm"},       {"planning", "scheduler"},
      {"arm", "scheduler"}};
  for (const auto& [host, name] : victims) {
    const auto before = watch.process(host, name);
    ASSERT_TRUE(before && before->state == "running") << name;
    const int64_t t0 = mono_ns();
    ASSERT_EQ(kill(before->pid, SIGKILL), 0) << name;
    ASSERT_TRUE(wait_until(
        [&] {
          auto s = watch.process(host, name);
          return s && s->state == "running" && s->pid != before->pid;
        },
        seconds(5)))
        << name;
    const double restart_s = static_cast<double>(mono_ns() - t0) * 1e-9;
    const int64_t states = watch.arm_states();
    const int64_t tracked = watch.tracked();
    EXPECT_TRUE(wait_until(
        [&] { return watch.arm_states() > states + 50 && watch.tracked() > tracked + 10; },
        seconds(15)))
        << "the system did not go on after kill -9 of " << name;
    const double flowing_s = static_cast<double>(mono_ns() - t0) * 1e-9;
    std::fprintf(stderr,
                 "shepherd across the LAN: kill -9 %s@%s: running again %.3f s, arm state and "
                 "tracks flowing %.3f s\n",
                 name.c_str(), host.c_str(), restart_s, flowing_s);
    EXPECT_LT(restart_s, 1.0) << name;
  }

  // The planner (planning machine) sends the arm (arm machine) somewhere
  // through comm, all of them restarted: the arm acknowledges a command
  // across the LAN.
  const int64_t acks = watch.arm_acks();
  EXPECT_TRUE(wait_until([&] { return watch.arm_acks() > acks; }, seconds(40)));
  // Stop all: the monitor writes its summary.
  ASSERT_EQ(run_to_end(p, "down", {m, "stop", "all", "--timeout", "20"}), 0);
  nlohmann::json s;
  std::ifstream(summary) >> s;
  std::fprintf(stderr, "summary: %s\n", s.dump().c_str());
  EXPECT_GE(s["arm_commands"].get<int>(), 1);  // planner (planning) -> comm -> arm (arm machine)
  EXPECT_GE(s["vision_rate_hz"].get<double>(), 25.0);
  EXPECT_TRUE(s["scheduler_seen"].get<bool>());
}

// The shepherding system across the two machines herds: 40 s of simulated
// time (the first saves come within 20 s) with three sheep at the paper's speed (its Lego sheep
// moved 5-8 mm/s; at the default 30 mm/s the arm cannot yet keep three or four, see the README's
// Performance section) end with every sheep on the field.
TEST_F(Lan, ThreeSheepStayOnTheFieldAcrossTwoMachines) {
  const std::string m = lan_shepherd_manifest("shepherd_herd.pbtxt");
  const std::string url = kShepherdLanUrl;
  Processes p;
  Watch watch(url);
  start_two_machines(p, 5, url, {"--quiet"});
  ASSERT_EQ(shepherd_up(p, m, {"--sheep", "3", "--sheep-speed", "8"}), 0);
  ASSERT_TRUE(wait_until([&] { return watch.herd().sim_time_s >= 40.0; }, seconds(70)))
      << "simulated time reached only " << watch.herd().sim_time_s << " s";
  const auto herd = watch.herd();
  std::fprintf(stderr, "3 sheep across the LAN, 40 s: %d escapes, %d saves, %zu arm commands\n",
               herd.escapes, herd.saves, watch.commands_acked());
  EXPECT_EQ(herd.escapes, 0);
  EXPECT_GE(watch.commands_acked(), 1u);  // planner (planning) -> comm -> arm (arm machine)
  ASSERT_EQ(run_to_end(p, "down", {m, "stop", "all", "--timeout", "20"}), 0);
}

// Item 5 of issue 6 on the deputies' side: 5 % packet loss each way on the
// arm machine's link (iptables' statistic match inside its namespace; this
// kernel has no sch_netem). The sheriff reports no host lost, the arm keeps
// acknowledging commands, and the arm executes no command twice (its
// accepted + rejected commands never exceed the commands comm sent; comm's
// retransmissions are answered as repeats).
TEST_F(Lan, ShepherdWithFivePercentLossOnTheArmLink) {
  const std::string m = lan_shepherd_manifest("shepherd_loss.pbtxt");
  const std::string url = kShepherdLanUrl;
  Processes p;
  Watch watch(url);
  start_two_machines(p, 4, url);
  ASSERT_EQ(shepherd_up(p, m, {"--sheep", "2"}), 0);
  const std::string in_arm = "nsenter -t " + std::to_string(watch.deputy_pid("arm")) + " -n ";
  run(in_arm + "iptables -A INPUT -i eth0 -m statistic --mode random --probability 0.05 -j DROP");
  run(in_arm + "iptables -A OUTPUT -o eth0 -m statistic --mode random --probability 0.05 -j DROP");
  p.start("sheriff", bin("ephor-sheriff"), {m, "--headless", "--seed", "7", "--sheep", "2"});
  const size_t acked = watch.commands_acked();
  const int64_t t0 = mono_ns();
  EXPECT_TRUE(wait_until([&] { return watch.commands_acked() >= acked + 6; }, seconds(90)))
      << "the arm answered " << watch.commands_acked() - acked << " new commands under 5 % loss";
  std::fprintf(stderr, "6 new arm commands answered under loss after %.1f s\n",
               static_cast<double>(mono_ns() - t0) * 1e-9);
  EXPECT_FALSE(p.has_line("sheriff", "deputy lost"));
  // Proof that packets were dropped: the rules' counters.
  run(in_arm + "iptables -L -v -n -x | grep statistic >&2");

  p.signal("sheriff", SIGTERM);
  ASSERT_TRUE(wait_until([&] { return exit_of(p, "sheriff").has_value(); }, seconds(5)));
  ASSERT_EQ(run_to_end(p, "down", {m, "stop", "all", "--timeout", "20"}), 0);
  // The processes' last words, through their deputies.
  std::smatch match;
  int accepted = -1, rejected = -1, commands = -1, retransmissions = -1;
  for (const auto& line : p.lines("deputy_arm"))
    if (std::regex_search(line, match, std::regex(R"(commands: (\d+) accepted, (\d+) rejected)"))) {
      accepted = std::stoi(match[1]);
      rejected = std::stoi(match[2]);
      std::fprintf(stderr, "arm: %s\n", line.c_str());
    }
  for (const auto& line : p.lines("deputy_planning"))
    if (std::regex_search(line, match, std::regex(R"(commands (\d+) \+ (\d+) retransmissions)"))) {
      commands = std::stoi(match[1]);
      retransmissions = std::stoi(match[2]);
      std::fprintf(stderr, "comm: %s\n", line.c_str());
    }
  ASSERT_GE(accepted, 0) << "no summary line from the arm";
  ASSERT_GE(commands, 0) << "no summary line from comm";
  EXPECT_GE(commands, 6);
  EXPECT_LE(accepted + rejected, commands) << "a command was executed twice";
  std::fprintf(stderr, "5 %% loss on the arm link: %d commands, %d retransmissions, %d accepted\n",
               commands, retransmissions, accepted);
}

}  // namespace
}  // namespace ephor::testing
