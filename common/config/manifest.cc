#include "common/config/manifest.h"

#include <cmath>
#include <cstdlib>
#include <memory>
#include <regex>
#include <set>

#include "common/config/text_proto.h"

namespace ephor {
namespace {

bool finite_nonneg(double v) { return std::isfinite(v) && v >= 0.0; }

void validate_and_fill(config::Manifest& m, const TextProto& src) {
  static const std::regex kName("[A-Za-z][A-Za-z0-9_-]*");
  if (m.name().empty()) src.fail("name", "a manifest needs a name");

  auto* lcm = m.mutable_lcm();
  if (lcm->group().empty()) lcm->set_group("239.255.76.67");
  if (lcm->port() == 0) lcm->set_port(7667);
  if (lcm->port() > 65535) src.fail("lcm.port", "must be 1..65535");
  if (lcm->ttl() > 1)
    src.fail("lcm.ttl", "must be 0 (this host) or 1 (LAN); larger TTLs leave the lab network");
  if (lcm->recv_buf_size() == 0) lcm->set_recv_buf_size(16u << 20);

  auto* sched = m.mutable_scheduler();
  if (sched->status_period_s() == 0.0) sched->set_status_period_s(1.0);
  if (!(std::isfinite(sched->status_period_s()) && sched->status_period_s() > 0.0))
    src.fail("scheduler.status_period_s", "must be a positive number of seconds");
  if (!finite_nonneg(sched->utilisation_bound()) || sched->utilisation_bound() > 1.0)
    src.fail("scheduler.utilisation_bound", "must be in [0, 1] (0 = Liu & Layland)");
  if (sched->history() == 0) sched->set_history(1000);
  if (sched->estimate_window() == 0) sched->set_estimate_window(3);
  if (sched->fifo_priority_max() == 0) sched->set_fifo_priority_max(80);
  if (sched->fifo_priority_max() < 1 || sched->fifo_priority_max() > 99)
    src.fail("scheduler.fifo_priority_max", "must be 1..99");
  if (!sched->has_migrate()) sched->set_migrate(true);
  if (!sched->has_cpu_latency_us()) sched->set_cpu_latency_us(0);
  if (sched->cpu_latency_us() < -1 || sched->cpu_latency_us() > 1000000)
    src.fail("scheduler.cpu_latency_us", "must be -1 (no request) or 0..1000000 us (got " +
                                             std::to_string(sched->cpu_latency_us()) + ")");
  for (int i = 0; i < sched->cpus_size(); ++i)
    if (sched->cpus(i) < 0) src.fail("scheduler.cpus[" + std::to_string(i) + "]", "negative CPU");

  std::set<std::string> hosts;
  for (int i = 0; i < m.host_size(); ++i) {
    const std::string field = "host[" + std::to_string(i) + "]";
    if (!std::regex_match(m.host(i).name(), kName))
      src.fail(field + ".name", "missing or not a plain name");
    if (!hosts.insert(m.host(i).name()).second)
      src.fail(field + ".name", "duplicate host '" + m.host(i).name() + "'");
  }
  if (m.host_size() == 0) {
    m.add_host()->set_name("local");
    hosts.insert("local");
  }

  std::set<std::string> params;
  for (int i = 0; i < m.param_size(); ++i) {
    const std::string field = "param[" + std::to_string(i) + "]";
    if (!std::regex_match(m.param(i).name(), std::regex("[a-z][a-z0-9_-]*")))
      src.fail(field + ".name", "missing or not a lower-case name");
    if (!params.insert(m.param(i).name()).second)
      src.fail(field + ".name", "duplicate parameter '" + m.param(i).name() + "'");
  }

  std::set<std::string> processes;
  for (int p = 0; p < m.process_size(); ++p) {
    auto* proc = m.mutable_process(p);
    const std::string pf = "process[" + std::to_string(p) + "]";
    if (!std::regex_match(proc->name(), kName))
      src.fail(pf + ".name", "missing or not a plain name");
    if (!processes.insert(proc->name()).second)
      src.fail(pf + ".name", "duplicate process '" + proc->name() + "'");
    if (proc->exec().empty())
      src.fail(pf + ".exec", "missing: which binary runs process '" + proc->name() + "'");
    if (proc->host().empty()) proc->set_host(m.host(0).name());
    if (!hosts.count(proc->host()))
      src.fail(pf + ".host",
               "unknown host '" + proc->host() + "' (declare it in a host { } block)");
    for (int a = 0; a < proc->args_size(); ++a) {
      static const std::regex kRef("\\$\\{([^}]*)\\}");
      const std::string& arg = proc->args(a);
      for (auto it = std::sregex_iterator(arg.begin(), arg.end(), kRef);
           it != std::sregex_iterator(); ++it)
        if (!params.count((*it)[1].str()))
          src.fail(pf + ".args[" + std::to_string(a) + "]",
                   "refers to undeclared parameter '" + (*it)[1].str() + "'");
    }

    std::set<std::string> tasks;
    for (int t = 0; t < proc->task_size(); ++t) {
      auto* task = proc->mutable_task(t);
      const std::string tf = pf + ".task[" + std::to_string(t) + "]";
      if (!std::regex_match(task->name(), kName))
        src.fail(tf + ".name", "missing or not a plain name");
      if (!tasks.insert(task->name()).second)
        src.fail(tf + ".name", "duplicate task '" + task->name() + "'");
      if (task->kind() == config::Task::KIND_UNSPECIFIED)
        src.fail(tf + ".kind", "missing: PERIODIC or TRIGGERED");
      if (!finite_nonneg(task->period_ms()))
        src.fail(tf + ".period_ms", "must be a finite number >= 0");
      if (!finite_nonneg(task->deadline_ms()))
        src.fail(tf + ".deadline_ms", "must be a finite number >= 0");
      if (!finite_nonneg(task->expected_exec_ms()))
        src.fail(tf + ".expected_exec_ms", "must be a finite number >= 0");
      if (task->kind() == config::Task::PERIODIC) {
        if (task->period_ms() <= 0.0)
          src.fail(tf + ".period_ms", "a PERIODIC task needs period_ms > 0");
        if (task->deadline_ms() == 0.0) task->set_deadline_ms(task->period_ms());
      } else if (task->deadline_ms() <= 0.0) {
        src.fail(tf + ".deadline_ms", "a TRIGGERED task needs deadline_ms > 0");
      }
      if (task->priority() < 0 || task->priority() > 99)
        src.fail(tf + ".priority", "must be 1..99, or 0 for rate-monotonic");
      if (task->policy() == config::Task::POLICY_UNSPECIFIED) task->set_policy(config::Task::FIFO);
      if (task->cpu().empty()) task->set_cpu("auto");
      if (task->cpu() != "auto" && !std::regex_match(task->cpu(), std::regex("[0-9]{1,4}")))
        src.fail(tf + ".cpu",
                 "must be \"auto\" or a CPU index like \"1\", not \"" + task->cpu() + "\"");
    }
  }
}

}  // namespace

config::Manifest load_manifest(const std::string& path) {
  config::Manifest m;
  TextProto src(path, &m);
  validate_and_fill(m, src);
  return m;
}

config::Manifest parse_manifest(const std::string& text, const std::string& name) {
  config::Manifest m;
  auto src = TextProto::from_string(text, name, &m);
  validate_and_fill(m, *src);
  return m;
}

std::string manifest_lcm_url(const config::Manifest& m) {
  return "udpm://" + m.lcm().group() + ":" + std::to_string(m.lcm().port()) +
         "?ttl=" + std::to_string(m.lcm().ttl()) +
         "&recv_buf_size=" + std::to_string(m.lcm().recv_buf_size());
}

std::string lcm_url_with_receive_buffer(const std::string& url, long long bytes) {
  static const std::string kKey = "recv_buf_size=";
  const auto at = url.find(kKey);
  if (at == std::string::npos) {
    return url + (url.find('?') == std::string::npos ? "?" : "&") + kKey + std::to_string(bytes);
  }
  const auto begin = at + kKey.size();
  const auto end = url.find('&', begin);
  const long long now = std::atoll(url.substr(begin, end - begin).c_str());
  if (now >= bytes) return url;
  return url.substr(0, begin) + std::to_string(bytes) +
         (end == std::string::npos ? "" : url.substr(end));
}

std::vector<std::string> manifest_hosts(const config::Manifest& m) {
  std::vector<std::string> out;
  for (const auto& h : m.host()) out.push_back(h.name());
  return out;
}

std::vector<std::string> expand_args(const config::Process& process,
                                     const std::map<std::string, std::string>& values) {
  static const std::regex kRef("\\$\\{([^}]*)\\}");
  std::vector<std::string> out;
  for (const std::string& arg : process.args()) {
    std::string result;
    bool empty_param = false;
    auto last = arg.cbegin();
    for (auto it = std::sregex_iterator(arg.begin(), arg.end(), kRef); it != std::sregex_iterator();
         ++it) {
      result.append(last, arg.cbegin() + it->position());
      auto v = values.find((*it)[1].str());
      const std::string value = v == values.end() ? "" : v->second;
      empty_param = empty_param || value.empty();
      result += value;
      last = arg.cbegin() + it->position() + it->length();
    }
    result.append(last, arg.cend());
    if (!empty_param) out.push_back(result);
  }
  return out;
}

int task_cpu(const config::Task& task) {
  return (task.cpu().empty() || task.cpu() == "auto") ? -1 : std::stoi(task.cpu());
}

}  // namespace ephor
