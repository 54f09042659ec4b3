// ephor-bench-sched: release jitter of a 1 kHz periodic task, measured the
// way the task runtime releases jobs (absolute clock_nanosleep on
// CLOCK_MONOTONIC, PeriodicRelease), under five conditions:
//   SCHED_OTHER idle, SCHED_FIFO idle, SCHED_FIFO idle holding a CPU wake-up
//   latency request of 0 us (PM QoS, as ephor-scheduler does while a system
//   runs), SCHED_OTHER + CPU hog, SCHED_FIFO + CPU hog
// (the hog is a busy loop pinned to the same CPU), and cyclictest (rt-tests,
// which makes the same PM QoS request by default)
// with the same interval, priority, CPU and duration as the peer, idle and
// with the hog, in the same run.
//
//   ephor-bench-sched --json out.json [--duration 30] [--cpu 1] [--priority 80]

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/runtime/cpu_latency_request.h"
#include "common/runtime/periodic_release.h"
#include "common/runtime/process_args.h"
#include "common/runtime/thread_sched.h"
#include "common/time/clock.h"

namespace {

using namespace ephor;

struct Result {
  std::string name;
  bool fifo = false;
  bool hog = false;
  bool rt_granted = true;
  double p50 = 0, p99 = 0, max = 0;  // us
  int64_t samples = 0;
};

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  const size_t k =
      std::min(v.size() - 1, static_cast<size_t>(p / 100.0 * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

// A busy loop pinned to `cpu` (SCHED_OTHER, nice 0) in a child process.
pid_t start_hog(int cpu) {
  const pid_t pid = fork();
  if (pid == 0) {
    apply_to_calling_thread({cpu, Policy::kOther, 0});
    volatile uint64_t x = 0;
    while (true) x = x + 1;
  }
  return pid;
}

void stop_hog(pid_t pid) {
  if (pid <= 0) return;
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
}

Result measure(const std::string& name, bool fifo, bool hog, int cpu, int priority,
               double duration_s, int64_t period_ns, bool cpu_latency_request = false) {
  // What ephor-scheduler holds while a system runs (and cyclictest holds by
  // default): idle CPUs poll instead of halting.
  std::unique_ptr<CpuLatencyRequest> wake_up;
  if (cpu_latency_request) {
    wake_up = std::make_unique<CpuLatencyRequest>(0);
    if (!wake_up->held()) std::fprintf(stderr, "warning: %s\n", wake_up->error().c_str());
  }
  Result r;
  r.name = name;
  r.fifo = fifo;
  r.hog = hog;
  const pid_t hog_pid = hog ? start_hog(cpu) : -1;
  const SchedOutcome out =
      apply_to_calling_thread({cpu, fifo ? Policy::kFifo : Policy::kOther, priority});
  r.rt_granted = !fifo || out.policy_ok;
  const int64_t n = static_cast<int64_t>(duration_s * 1e9 / static_cast<double>(period_ns));
  std::vector<double> latency;
  latency.reserve(static_cast<size_t>(n));
  PeriodicRelease release(mono_ns() + 10 * period_ns, period_ns);
  for (int64_t i = 0; i < n; ++i) {
    sleep_until_mono_ns(release.next_release_ns());
    const int64_t now = mono_ns();
    latency.push_back(static_cast<double>(now - release.next_release_ns()) / 1000.0);
    release.advance(now);
  }
  apply_to_calling_thread({-1, Policy::kOther, 0});
  stop_hog(hog_pid);
  r.samples = static_cast<int64_t>(latency.size());
  r.p50 = percentile(latency, 50);
  r.p99 = percentile(latency, 99);
  r.max = *std::max_element(latency.begin(), latency.end());
  return r;
}

// Runs cyclictest with the same interval, priority, CPU and duration; reads
// its histogram (1 us buckets up to 10 ms) for p50/p99 and its max.
Result cyclictest(const std::string& name, bool hog, int cpu, int priority, double duration_s,
                  int64_t period_ns) {
  Result r;
  r.name = name;
  r.fifo = true;
  r.hog = hog;
  const pid_t hog_pid = hog ? start_hog(cpu) : -1;
  std::ostringstream cmd;
  cmd << "cyclictest -m -q -t1 -a " << cpu << " -p " << priority << " -i " << period_ns / 1000
      << " -D " << static_cast<int>(duration_s) << " -h 10000 2>&1";
  FILE* p = popen(cmd.str().c_str(), "r");
  std::vector<std::pair<int, int64_t>> hist;
  char line[512];
  int64_t total = 0;
  while (p != nullptr && std::fgets(line, sizeof line, p) != nullptr) {
    int bucket = 0;
    long long count = 0;
    long long value = 0;
    if (line[0] != '#' && std::sscanf(line, "%d %lld", &bucket, &count) == 2) {
      hist.emplace_back(bucket, count);
      total += count;
    } else if (std::sscanf(line, "# Max Latencies: %lld", &value) == 1) {
      r.max = static_cast<double>(value);
    } else if (std::strstr(line, "Operation not permitted") != nullptr) {
      r.rt_granted = false;
    }
  }
  if (p != nullptr) pclose(p);
  stop_hog(hog_pid);
  r.samples = total;
  int64_t seen = 0;
  bool have50 = false;
  for (const auto& [bucket, count] : hist) {
    seen += count;
    if (!have50 && seen * 2 >= total) {
      r.p50 = bucket;
      have50 = true;
    }
    if (seen * 100 >= total * 99) {
      r.p99 = bucket;
      break;
    }
  }
  return r;
}

nlohmann::json to_json(const Result& r) {
  return {{"name", r.name},  {"policy", r.fifo ? "SCHED_FIFO" : "SCHED_OTHER"},
          {"hog", r.hog},    {"rt_granted", r.rt_granted},
          {"p50_us", r.p50}, {"p99_us", r.p99},
          {"max_us", r.max}, {"samples", r.samples}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ephor-bench-sched: release jitter of a 1 kHz task vs cyclictest"};
  std::string json_path;
  double duration_s = 30.0;
  int cpu = 1;
  int priority = 80;
  double period_us = 1000.0;
  app.add_option("--json", json_path, "write results as JSON here");
  app.add_option("--duration", duration_s, "seconds per condition (>= 30 for the README figures)")
      ->check(CLI::PositiveNumber);
  app.add_option("--cpu", cpu, "CPU to measure on (the hog is pinned there too)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--priority", priority, "SCHED_FIFO priority")->check(CLI::Range(1, 99));
  app.add_option("--period-us", period_us, "release period, us (1000 = 1 kHz)")
      ->check(CLI::PositiveNumber);
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  if (cpu >= online_cpus()) {
    std::fprintf(stderr, "--cpu %d: this machine has %d online CPUs\n", cpu, online_cpus());
    return 2;
  }
  const int64_t period_ns = static_cast<int64_t>(period_us * 1000.0);
  const std::string locked = lock_process_memory();
  if (!locked.empty()) std::fprintf(stderr, "warning: %s\n", locked.c_str());

  std::printf("release jitter of a %.0f us periodic task on CPU %d, %.0f s per condition\n",
              period_us, cpu, duration_s);
  std::vector<Result> results;
  auto run = [&](Result r) {
    std::printf("  %-26s p50 %7.1f  p99 %7.1f  max %8.1f us  (%lld samples%s)\n", r.name.c_str(),
                r.p50, r.p99, r.max, static_cast<long long>(r.samples),
                r.rt_granted ? "" : ", SCHED_FIFO REFUSED");
    std::fflush(stdout);
    results.push_back(r);
  };
  run(measure("ephor SCHED_OTHER idle", false, false, cpu, priority, duration_s, period_ns));
  run(measure("ephor SCHED_FIFO idle", true, false, cpu, priority, duration_s, period_ns));
  run(measure("ephor SCHED_FIFO idle, PM QoS 0", true, false, cpu, priority, duration_s, period_ns,
              true));
  run(measure("ephor SCHED_OTHER + hog", false, true, cpu, priority, duration_s, period_ns));
  run(measure("ephor SCHED_FIFO + hog", true, true, cpu, priority, duration_s, period_ns));
  run(cyclictest("cyclictest idle", false, cpu, priority, duration_s, period_ns));
  run(cyclictest("cyclictest + hog", true, cpu, priority, duration_s, period_ns));

  const Result& ours = results[4];
  const Result& peer = results[6];
  const double ratio = peer.max > 0 ? ours.max / peer.max : 0.0;
  const bool p99_ok = ours.p99 < 100.0;
  const bool max_ok = ratio > 0 && ratio <= 2.0;
  std::printf(
      "with the hog: SCHED_FIFO p99 %.1f us (target < 100: %s); max %.1f us vs cyclictest %.1f us, "
      "ratio %.2f (target <= 2: %s)\n",
      ours.p99, p99_ok ? "met" : "MISSED", ours.max, peer.max, ratio, max_ok ? "met" : "MISSED");

  if (!json_path.empty()) {
    nlohmann::json j;
    j["benchmark"] = "sched";
    j["period_us"] = period_us;
    j["cpu"] = cpu;
    j["priority"] = priority;
    j["duration_s_per_condition"] = duration_s;
    j["results"] = nlohmann::json::array();
    for (const auto& r : results) j["results"].push_back(to_json(r));
    j["fifo_hog_vs_cyclictest_max_ratio"] = ratio;
    j["target_p99_under_100us"] = p99_ok;
    j["target_max_within_2x_cyclictest"] = max_ok;
    std::ofstream(json_path) << j.dump(2) << "\n";
    std::printf("wrote %s\n", json_path.c_str());
  }
  return 0;
}
