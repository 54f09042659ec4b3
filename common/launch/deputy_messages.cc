#include "common/launch/deputy_messages.h"

#include <unistd.h>

#include <cstdio>
#include <functional>
#include <stdexcept>

namespace ephor::deputy {

std::string deputy_tag(const DeputySettings& settings) {
  return settings.host + "@" + settings.lcm_url;
}

std::vector<ProcessOrder> host_orders(const deputy_orders_t& orders,
                                      const DeputySettings& settings) {
  if (orders.host != settings.host)
    throw std::invalid_argument("orders for host '" + orders.host + "', this deputy is '" +
                                settings.host + "'");
  if (orders.num_processes < 0 ||
      static_cast<size_t>(orders.num_processes) != orders.processes.size())
    throw std::invalid_argument("orders: num_processes " + std::to_string(orders.num_processes) +
                                " but " + std::to_string(orders.processes.size()) + " processes");
  // A string with a NUL byte inside (lcm-gen's decoder kept it; ours now
  // refuse the message, cmake/lcm_bound_counts.sed, so this guards orders
  // built in process) cannot reach
  // execve or the environment whole, and LCM's encoder stops at the NUL
  // while getEncodedSize() counts past it, so the deputy's status would
  // carry a name its receivers drop as a short message (found by
  // fuzz_deputy_orders).
  auto check_text = [](const std::string& text, const std::string& what) {
    if (text.find('\0') != std::string::npos)
      throw std::invalid_argument("orders: " + what + " contains a NUL byte");
  };
  check_text(orders.sheriff, "the sheriff's name");
  check_text(orders.manifest_text, "the manifest");
  check_text(orders.lcm_url, "the LCM URL");
  for (const auto& p : orders.processes) {
    check_text(p.name, "a process name");
    check_text(p.exec, "process '" + p.name + "': its exec");
    for (const auto& a : p.args) check_text(a, "process '" + p.name + "': an argument");
  }
  const std::string url = orders.lcm_url.empty() ? settings.lcm_url : orders.lcm_url;
  const std::string tag = deputy_tag(settings);
  auto env_for = [&](const std::string& name) {
    return std::vector<std::pair<std::string, std::string>>{
        {"EPHOR_LAUNCHED", "1"},
        {"EPHOR_PROCESS", name},
        {"EPHOR_HOST", settings.host},
        {"EPHOR_MANIFEST", settings.manifest_path},
        {"EPHOR_BIN_DIR", settings.bin_dir},
        {"LCM_DEFAULT_URL", url},
        {kDeputyTagVariable, tag}};
  };
  std::vector<ProcessOrder> out;
  if (orders.start_scheduler) {
    if (orders.manifest_text.empty())
      throw std::invalid_argument("orders ask for the scheduler but carry no manifest");
    ProcessOrder s;
    s.name = kSchedulerRow;
    s.exec = "ephor-scheduler";
    s.args = {"--manifest", settings.manifest_path, "--host", settings.host};
    s.env = env_for(s.name);
    // A new manifest restarts the scheduler (it reads its task table at start).
    char hash[32];
    std::snprintf(hash, sizeof hash, "%zx", std::hash<std::string>{}(orders.manifest_text));
    s.env.emplace_back("EPHOR_MANIFEST_HASH", hash);
    out.push_back(std::move(s));
  }
  for (const auto& p : orders.processes) {
    if (p.name.empty()) throw std::invalid_argument("orders: a process without a name");
    if (p.exec.empty()) throw std::invalid_argument("orders: process '" + p.name + "' has no exec");
    if (p.num_args < 0 || static_cast<size_t>(p.num_args) != p.args.size())
      throw std::invalid_argument("orders: process '" + p.name + "': num_args disagrees");
    if (orders.start_scheduler && p.name == kSchedulerRow)
      throw std::invalid_argument(
          "orders: a process named 'scheduler' clashes with the host's ephor-scheduler");
    for (const auto& o : out)
      if (o.name == p.name)
        throw std::invalid_argument("orders name process '" + p.name + "' twice");
    ProcessOrder o;
    o.name = p.name;
    o.exec = p.exec;
    o.args = p.args;
    o.env = env_for(p.name);
    o.run = p.run;
    o.run_id = p.run_id < 0 ? -1 : p.run_id;
    o.allow_exit = p.allow_exit;
    out.push_back(std::move(o));
  }
  return out;
}

deputy_status_t make_status(const ProcessTable& table, const std::map<pid_t, UsageSample>& usage,
                            const DeputySettings& settings, int64_t orders_utime,
                            const std::string& sheriff, int64_t now_ns) {
  deputy_status_t s{};
  s.host = settings.host;
  s.deputy_pid = static_cast<int32_t>(getpid());
  s.orders_utime = orders_utime;
  s.sheriff = sheriff;
  double load[1] = {0.0};
  s.cpu_load = getloadavg(load, 1) == 1 ? static_cast<float>(load[0]) : -1.0f;
  for (const auto& r : table.rows()) {
    deputy_process_status_t p{};
    p.name = r.order.name;
    p.state = to_string(r.state);
    p.run = r.order.run;
    p.run_id = r.run_id;
    p.pid = static_cast<int32_t>(r.pid);
    p.restarts = r.restarts;
    p.exit_code = r.exit_code;
    p.exit_signal = r.exit_signal;
    p.reason = r.reason;
    if (auto it = usage.find(r.pid); r.pid != 0 && it != usage.end()) {
      p.cpu_percent = it->second.cpu_percent;
      p.rss_bytes = it->second.rss_bytes;
    }
    p.uptime_us = r.pid != 0 ? (now_ns - r.started_ns) / 1000 : 0;
    s.processes.push_back(p);
  }
  s.num_processes = static_cast<int32_t>(s.processes.size());
  return s;
}

}  // namespace ephor::deputy
