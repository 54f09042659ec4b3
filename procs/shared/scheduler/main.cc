// ephor-scheduler: the user-level scheduler of one host (paper 003, 3.1).
//
// Reads the task table of the deployment manifest for its host, publishes
// the assignment table (EPHOR_SCHED_ASSIGN: CPU, policy, priority, period per
// task) at start, on every change and at the status period; collects task
// registrations and per-job statistics; migrates "auto" tasks off CPUs whose
// measured utilisation passes the schedulable bound; publishes
// EPHOR_SCHED_STATUS at the status period (1 Hz by default).

#include <iostream>
#include <memory>
#include <mutex>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/config/manifest.h"
#include "common/config/text_proto.h"
#include "common/lcm/bus.h"
#include "common/log/log.h"
#include "common/runtime/channels.h"
#include "common/runtime/cpu_latency_request.h"
#include "common/runtime/process_args.h"
#include "common/time/clock.h"
#include "ephor/sched_assignments_t.hpp"
#include "ephor/sched_status_t.hpp"
#include "ephor/task_jobs_t.hpp"
#include "ephor/task_register_t.hpp"
#include "procs/shared/scheduler/scheduler.h"
#include "procs/shared/scheduler/task_messages.h"
#include "procs/shared/scheduler/task_table.h"

namespace {

using namespace ephor;
using namespace ephor::scheduler;

sched_assignments_t to_msg(const std::vector<Assignment>& rows, const std::string& host) {
  sched_assignments_t msg{};
  msg.utime = wall_us();
  msg.host = host;
  for (const auto& a : rows) {
    task_assignment_t t{};
    t.utime = msg.utime;
    t.process = a.process;
    t.task = a.task;
    t.cpu = a.cpu;
    t.policy = a.policy == Policy::kFifo ? task_assignment_t::POLICY_FIFO
                                         : task_assignment_t::POLICY_OTHER;
    t.priority = a.priority;
    t.period_us = a.period_us;
    t.deadline_us = a.deadline_us;
    t.generation = a.generation;
    msg.tasks.push_back(t);
  }
  msg.num_tasks = static_cast<int32_t>(msg.tasks.size());
  return msg;
}

sched_status_t to_msg(const HostStatus& hs, const std::vector<std::string>& events,
                      const std::string& host) {
  sched_status_t msg{};
  msg.utime = wall_us();
  msg.host = host;
  msg.rt = hs.rt;
  msg.num_cpus = static_cast<int32_t>(hs.cpus.size());
  for (size_t i = 0; i < hs.cpus.size(); ++i) {
    msg.cpu_utilisation.push_back(static_cast<float>(hs.cpu_utilisation[i]));
    msg.cpu_bound.push_back(static_cast<float>(hs.cpu_bound[i]));
  }
  for (const auto& ts : hs.tasks) {
    task_status_t t{};
    t.utime = msg.utime;
    t.process = ts.assignment.process;
    t.task = ts.assignment.task;
    t.pid = ts.pid;
    t.tid = ts.tid;
    t.cpu = ts.readback.ok ? ts.readback.cpu : -1;
    t.assigned_cpu = ts.assignment.cpu;
    t.policy = ts.readback.ok ? policy_name(ts.readback.policy) : "unknown";
    t.priority = ts.readback.priority;
    t.periodic = ts.periodic;
    t.period_us = ts.assignment.period_us;
    t.deadline_us = ts.assignment.deadline_us;
    t.exec_p50_us = static_cast<float>(ts.exec_p50);
    t.exec_p99_us = static_cast<float>(ts.exec_p99);
    t.exec_max_us = static_cast<float>(ts.exec_max);
    t.jitter_p50_us = static_cast<float>(ts.jitter_p50);
    t.jitter_p99_us = static_cast<float>(ts.jitter_p99);
    t.jitter_max_us = static_cast<float>(ts.jitter_max);
    t.jobs = ts.jobs;
    t.deadline_misses = ts.deadline_misses;
    t.utilisation = static_cast<float>(ts.utilisation);
    t.rt_granted = ts.rt_granted;
    t.alive = ts.alive;
    msg.tasks.push_back(t);
  }
  msg.num_tasks = static_cast<int32_t>(msg.tasks.size());
  msg.events = events;
  msg.num_events = static_cast<int32_t>(msg.events.size());
  return msg;
}

void print_table(const HostStatus& hs) {
  spdlog::info("{:<24} {:>5} {:>4} {:<11} {:>4} {:>9} {:>9} {:>9} {:>9} {:>6} {:>3}", "task", "pid",
               "cpu", "policy", "prio", "period_us", "exec_p99", "jit_p99", "jit_max", "misses",
               "rt");
  for (const auto& t : hs.tasks) {
    spdlog::info("{:<24} {:>5} {:>4} {:<11} {:>4} {:>9} {:>9.0f} {:>9.0f} {:>9.0f} {:>6} {:>3}",
                 t.assignment.process + "/" + t.assignment.task, t.pid, t.readback.cpu,
                 t.alive ? policy_name(t.readback.policy) : "-", t.readback.priority,
                 t.assignment.period_us, t.exec_p99, t.jitter_p99, t.jitter_max, t.deadline_misses,
                 t.rt_granted ? "yes" : "no");
  }
}

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{"ephor-scheduler: user-level scheduler of one host"};
  ProcessArgs args;
  add_process_flags(app, args, "scheduler");
  std::string manifest_path;
  double print_every_s = 10.0;
  app.add_option("--manifest", manifest_path, "deployment manifest (Protobuf text)")->required();
  app.add_option("--print-every", print_every_s,
                 "print the task table every S seconds (0 = never)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    const config::Manifest manifest = load_manifest(manifest_path);
    const auto& sc = manifest.scheduler();
    SchedulerConfig cfg;
    for (int c : sc.cpus()) cfg.cpus.push_back(c);
    if (cfg.cpus.empty())
      for (int c = 0; c < online_cpus(); ++c) cfg.cpus.push_back(c);
    for (int c : cfg.cpus)
      if (c >= online_cpus())
        spdlog::warn(
            "manifest names CPU {} but this host has {} online CPUs; tasks pinned there will be "
            "refused",
            c, online_cpus());
    cfg.fixed_bound = sc.utilisation_bound();
    cfg.history = sc.history();
    cfg.estimate_window = sc.estimate_window();
    cfg.fifo_priority_max = sc.fifo_priority_max();
    cfg.migrate = sc.migrate();

    // Held until the scheduler exits (the kernel drops it with the file).
    std::unique_ptr<CpuLatencyRequest> cpu_latency;
    const int cpu_latency_us = sc.cpu_latency_us();  // the manifest loader's default: 0
    if (cpu_latency_us >= 0) {
      cpu_latency = std::make_unique<CpuLatencyRequest>(cpu_latency_us);
      if (cpu_latency->held()) {
        spdlog::info("CPU wake-up latency held at {} us while this scheduler runs (idle CPUs poll)",
                     cpu_latency_us);
      } else {
        spdlog::warn(
            "CPU wake-up latency request of {} us refused ({}): idle CPUs may sleep and tasks "
            "wake later; run as root or set scheduler {{ cpu_latency_us: -1 }} to silence this",
            cpu_latency_us, cpu_latency->error());
      }
    }

    auto table = build_task_table(manifest, args.host);
    if (table.empty()) spdlog::warn("no tasks for host '{}' in {}", args.host, manifest_path);
    Scheduler sched(cfg, table);

    // --lcm-url, else $LCM_DEFAULT_URL (set by the launcher), else the manifest's.
    const bool env_url = std::getenv("LCM_DEFAULT_URL") != nullptr;
    const std::string url = resolve_lcm_url(
        !args.lcm_url.empty() || env_url ? args.lcm_url : manifest_lcm_url(manifest));
    Bus bus(url, args.name);
    std::mutex mutex;
    bool publish_now = true;
    bus.subscribe<task_register_t>(channels::kTaskRegister, [&](const task_register_t& m) {
      const auto r = registration_of(m, args.host);
      if (!r) return;
      std::lock_guard<std::mutex> lock(mutex);
      sched.on_register(*r, mono_us());
      publish_now = true;  // a (re)started task should not wait a whole period for its assignment
    });
    bus.subscribe<task_jobs_t>(channels::kTaskJobs, [&](const task_jobs_t& m) {
      const auto r = jobs_report_of(m, args.host);
      if (!r) return;
      std::lock_guard<std::mutex> lock(mutex);
      sched.on_jobs(*r, mono_us());
    });
    bus.start();
    spdlog::info("scheduling {} task(s) of host '{}' on CPUs [{}], status every {} s, LCM {}",
                 table.size(), args.host, fmt::join(cfg.cpus, ","), sc.status_period_s(), url);

    const int64_t period_us = static_cast<int64_t>(sc.status_period_s() * 1e6);
    int64_t next_status = mono_us();
    int64_t next_print = mono_us() + static_cast<int64_t>(print_every_s * 1e6);
    bool warned_rt = false;
    while (wait_for_shutdown_signal(0.02) == 0) {
      std::lock_guard<std::mutex> lock(mutex);
      const int64_t now = mono_us();
      if (now >= next_status) {
        for (const auto& e : sched.rebalance(now)) spdlog::warn("{}", e);
        for (const auto& refusal : sched.take_new_refusals()) {
          if (!warned_rt) {
            spdlog::warn(
                "SCHED_FIFO was refused ({}). Those tasks run under SCHED_OTHER and status reports "
                "rt=false: run as root, grant CAP_SYS_NICE, or raise RLIMIT_RTPRIO (ulimit -r 99).",
                refusal);
            warned_rt = true;
          } else {
            spdlog::info("SCHED_FIFO also refused for {}", refusal);
          }
        }
        const HostStatus hs = sched.status(now);
        auto status = to_msg(hs, sched.events(), args.host);
        bus.publish(channels::kSchedStatus, status);
        publish_now = true;
        next_status += period_us;
        if (next_status < now) next_status = now + period_us;
        if (print_every_s > 0 && now >= next_print) {
          print_table(hs);
          next_print = now + static_cast<int64_t>(print_every_s * 1e6);
        }
      }
      if (publish_now) {
        auto msg = to_msg(sched.assignments(), args.host);
        bus.publish(channels::kSchedAssign, msg);
        publish_now = false;
      }
    }
    bus.stop();
  } catch (const ConfigError& e) {
    // A bad --manifest: one line, status 2 (issue 18).
    std::cerr << "ephor-scheduler: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
