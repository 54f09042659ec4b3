// ephor-testtask: a process whose tasks only burn a given amount of CPU. Used
// by the scheduler's integration tests and the small demo manifest to show
// the task runtime and ephor-scheduler at work without any application.
//
//   ephor-testtask --task periodic:tick:10:500 --task triggered:save:2000
//     periodic:NAME:PERIOD_MS[:EXEC_US]   released every PERIOD_MS, runs EXEC_US
//     triggered:NAME[:EXEC_US]            released by task_trigger_t
//   --leak-kb-per-s N: also allocates and touches N KiB a second and never
//     frees it (a leak on purpose, for the launcher's memory report tests)

#include <algorithm>
#include <chrono>
#include <ctime>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/lcm/bus.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"

namespace {

// Nanoseconds of CPU this thread has used.
int64_t thread_cpu_ns() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

// Busy-waits until this thread has used `us` microseconds of CPU (a stand-in
// for real work: a fixed amount of computing, however often it is preempted).
// Wall time would let two tasks sharing a CPU split one burst between them,
// and the scheduler, which measures thread CPU time, would see half the load.
void burn_us(int64_t us) {
  const int64_t end = thread_cpu_ns() + us * 1000;
  while (thread_cpu_ns() < end) {
  }
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string part;
  while (std::getline(ss, part, sep)) out.push_back(part);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  ephor::block_shutdown_signals();
  CLI::App app{"ephor-testtask: tasks that burn CPU, for scheduler tests"};
  ephor::ProcessArgs args;
  ephor::add_process_flags(app, args, "testtask");
  std::vector<std::string> specs;
  double duration_s = 0.0;
  double leak_kb_per_s = 0.0;
  app.add_option("--task", specs, "periodic:NAME:PERIOD_MS[:EXEC_US] or triggered:NAME[:EXEC_US]")
      ->required();
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)");
  app.add_option("--leak-kb-per-s", leak_kb_per_s,
                 "allocate and keep this many KiB a second (a leak on purpose, for tests)")
      ->check(CLI::Range(0.0, 1e6));
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  ephor::init_logging(args.name);

  try {
    ephor::Bus bus(args.lcm_url, args.name);
    ephor::TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    for (const std::string& spec : specs) {
      const auto f = split(spec, ':');
      if (f.size() >= 3 && f[0] == "periodic") {
        const double period_ms = std::stod(f[2]);
        const int64_t exec_us = f.size() > 3 ? std::stoll(f[3]) : 0;
        if (!(period_ms > 0.0) || exec_us < 0)
          throw std::invalid_argument("bad task spec '" + spec + "'");
        runtime.add_periodic(f[1], std::chrono::nanoseconds(static_cast<int64_t>(period_ms * 1e6)),
                             [exec_us] { burn_us(exec_us); });
      } else if (f.size() >= 2 && f[0] == "triggered") {
        const int64_t exec_us = f.size() > 2 ? std::stoll(f[2]) : 0;
        if (exec_us < 0) throw std::invalid_argument("bad task spec '" + spec + "'");
        runtime.add_triggered(f[1], std::chrono::seconds(1), [exec_us] { burn_us(exec_us); });
      } else {
        throw std::invalid_argument(
            "bad task spec '" + spec +
            "' (want periodic:NAME:PERIOD_MS[:EXEC_US] or triggered:NAME[:EXEC_US])");
      }
    }
    runtime.start();
    spdlog::info("running {} task(s) on host {}", specs.size(), args.host);
    if (leak_kb_per_s > 0.0) {
      // Every 0.1 s a block, written so that it is resident, kept until exit.
      std::vector<std::unique_ptr<char[]>> leaked;
      const auto block = static_cast<size_t>(leak_kb_per_s * 1024.0 / 10.0);
      const auto end = std::chrono::steady_clock::now() +
                       std::chrono::duration<double>(duration_s > 0.0 ? duration_s : 1e9);
      while (std::chrono::steady_clock::now() < end && ephor::wait_for_shutdown_signal(0.1) == 0) {
        leaked.emplace_back(new char[block]);
        std::fill_n(leaked.back().get(), block, '\1');
      }
    } else {
      ephor::wait_for_shutdown_signal(duration_s);
    }
    runtime.stop();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
