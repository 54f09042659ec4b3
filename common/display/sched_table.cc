#include "common/display/sched_table.h"

#include "common/display/json_format.h"

namespace ephor::display {
namespace {

// Shares of a CPU, to 0.001; NaN and infinities (a corrupt status) as 0, which JSON can carry.
std::vector<double> rounded3(const std::vector<double>& xs) {
  std::vector<double> out;
  out.reserve(xs.size());
  for (const double x : xs) out.push_back(rounded(x, 3));
  return out;
}

}  // namespace

void SchedTable::on_sched(HostSched host) {
  const std::string name = host.host;
  hosts_[name] = std::move(host);
}

nlohmann::json SchedTable::to_json() const {
  using nlohmann::json;
  json hosts = json::array();
  for (const auto& [name, h] : hosts_) {
    json tasks = json::array();
    for (const auto& t : h.tasks) {
      tasks.push_back({{"process", t.process},
                       {"task", t.task},
                       {"cpu", t.cpu},
                       {"policy", t.policy},
                       {"priority", t.priority},
                       {"periodic", t.periodic},
                       {"period_us", t.period_us},
                       {"deadline_us", t.deadline_us},
                       {"exec_p50_us", r1(t.exec_p50_us)},
                       {"exec_p99_us", r1(t.exec_p99_us)},
                       {"exec_max_us", r1(t.exec_max_us)},
                       {"jitter_p50_us", r1(t.jitter_p50_us)},
                       {"jitter_p99_us", r1(t.jitter_p99_us)},
                       {"jitter_max_us", r1(t.jitter_max_us)},
                       {"jobs", t.jobs},
                       {"deadline_misses", t.deadline_misses},
                       {"utilisation", rounded(t.utilisation, 3)},
                       {"rt", t.rt_granted},
                       {"alive", t.alive}});
    }
    hosts.push_back({{"host", name},
                     {"rt", h.rt},
                     {"cpu_utilisation", rounded3(h.cpu_utilisation)},
                     {"cpu_bound", rounded3(h.cpu_bound)},
                     {"tasks", tasks},
                     {"events", h.events}});
  }
  return hosts;
}

}  // namespace ephor::display
