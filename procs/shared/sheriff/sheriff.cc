#include "procs/shared/sheriff/sheriff.h"

#include <google/protobuf/text_format.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <stdexcept>

#include "common/config/manifest.h"

namespace ephor::sheriff {
namespace {

constexpr const char* kScheduler = "scheduler";  // the deputies' row for ephor-scheduler

bool is_down_for_good(const std::string& state) { return state == "failed" || state == "finished"; }

bool is_stopped(const std::string& state) {
  return state == "stopped" || state == "failed" || state == "finished";
}

// `text` as one line of at most `max` characters, for the table and what
// converged() waits for: a deputy's row may hold any bytes (its names,
// state and reason), and a newline or a terminal's control sequence in them
// would break the table; a control character is shown as '?', a longer text
// is cut with "...". The caps keep a table line within its 512 bytes.
std::string printable(const std::string& text, size_t max) {
  std::string out;
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    out.push_back(u < 0x20 || u == 0x7f ? '?' : c);
  }
  if (out.size() > max) out = out.substr(0, max - 3) + "...";
  return out;
}
constexpr size_t kNameMax = 40;
constexpr size_t kStateMax = 12;
constexpr size_t kReasonMax = 160;

// Seconds with one decimal, e.g. "2.6".
std::string seconds_1dp(double s) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.1f", s);
  return buf;
}

}  // namespace

std::map<std::string, std::string> manifest_params(const config::Manifest& manifest,
                                                   const std::vector<std::string>& overrides) {
  std::map<std::string, std::string> params;
  for (const auto& p : manifest.param()) params[p.name()] = p.default_value();
  for (size_t i = 0; i < overrides.size(); ++i) {
    std::string name = overrides[i];
    std::string value;
    if (name.rfind("--", 0) != 0) throw std::invalid_argument("unexpected argument '" + name + "'");
    name = name.substr(2);
    if (const auto eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
    } else if (i + 1 < overrides.size()) {
      value = overrides[++i];
    } else {
      throw std::invalid_argument("--" + name + " needs a value");
    }
    if (!params.count(name)) {
      std::string known;
      for (const auto& [k, v] : params) known += " --" + k;
      throw std::invalid_argument("unknown option --" + name + " (parameters of the manifest:" +
                                  (known.empty() ? " none" : known) + ")");
    }
    params[name] = value;
  }
  return params;
}

Sheriff::Sheriff(config::Manifest manifest, SheriffOptions options)
    : manifest_(std::move(manifest)), options_(std::move(options)) {
  google::protobuf::TextFormat::PrintToString(manifest_, &manifest_text_);
  for (const auto& h : manifest_hosts(manifest_)) {
    HostView v;
    v.name = h;
    hosts_.push_back(v);
  }
  for (const auto& h : hosts_) {
    bool has_processes = false;
    for (const auto& p : manifest_.process()) has_processes = has_processes || p.host() == h.name;
    if (has_processes && options_.start_scheduler)
      processes_.push_back({h.name, kScheduler, false, true, -1, std::nullopt});
    for (const auto& p : manifest_.process()) {
      if (p.host() != h.name) continue;
      if (options_.start_scheduler && p.name() == kScheduler)
        throw std::invalid_argument(
            "process 'scheduler' clashes with the deputies' ephor-scheduler row; rename it");
      processes_.push_back({h.name, p.name(), true, false, -1, std::nullopt});
    }
  }
}

ProcessView* Sheriff::find_mutable(const std::string& host, const std::string& name) {
  for (auto& p : processes_)
    if (p.host == host && p.name == name) return &p;
  return nullptr;
}

const ProcessView* Sheriff::find(const std::string& host, const std::string& name) const {
  for (const auto& p : processes_)
    if (p.host == host && p.name == name) return &p;
  return nullptr;
}

HostView* Sheriff::find_host(const std::string& name) {
  for (auto& h : hosts_)
    if (h.name == name) return &h;
  return nullptr;
}

const HostView* Sheriff::find_host(const std::string& name) const {
  for (const auto& h : hosts_)
    if (h.name == name) return &h;
  return nullptr;
}

bool Sheriff::host_alive(const HostView& host, int64_t now_ns) const {
  return host.last_status_ns >= 0 && now_ns - host.last_status_ns < options_.lost_after_ns;
}

void Sheriff::on_status(const deputy_status_t& status, int64_t now_ns, int64_t receive_wall_us) {
  HostView* host = find_host(status.host);
  if (host == nullptr) return;
  if (receive_wall_us > 0 && status.utime > 0) {
    auto& recent = host->recent_offsets_us;
    recent.push_back(receive_wall_us - status.utime);
    if (recent.size() > 10) recent.erase(recent.begin());
    host->offset_plus_delay_us = *std::min_element(recent.begin(), recent.end());
  }
  host->last_status_ns = now_ns;
  host->deputy_pid = status.deputy_pid;
  host->orders_from = status.sheriff;
  host->load = status.cpu_load;
  for (auto& p : processes_)
    if (p.host == status.host) p.reported.reset();
  for (const auto& row : status.processes) {
    ProcessView* view = find_mutable(status.host, row.name);
    if (view == nullptr) {
      processes_.push_back({status.host, row.name, false, false, -1, std::nullopt});
      view = &processes_.back();
    }
    view->reported = row;
  }
  // Extras no deputy reports any more are gone.
  processes_.erase(std::remove_if(processes_.begin(), processes_.end(),
                                  [](const ProcessView& p) {
                                    return !p.in_manifest && p.name != kScheduler &&
                                           !p.reported.has_value();
                                  }),
                   processes_.end());
}

void Sheriff::adopt(bool default_run) {
  for (auto& p : processes_) {
    if (!p.in_manifest) continue;
    bool gui = false;
    for (const auto& m : manifest_.process()) gui = gui || (m.name() == p.name && m.gui());
    p.desired_run = p.reported ? p.reported->run : default_run && !(options_.headless && gui);
    p.desired_run_id = -1;
  }
}

void Sheriff::command(Command command, const std::string& target) {
  // A new run is the newest run id + 1; a deputy reporting the last id there
  // is leaves none (refused before anything changes, also for "all").
  for (const auto& p : processes_) {
    if (!p.in_manifest || (target != "all" && p.name != target)) continue;
    const bool new_run =
        command == Command::kRestart ||
        (command == Command::kStart && p.reported && is_down_for_good(p.reported->state));
    const int32_t reported_id = p.reported ? p.reported->run_id : -1;
    if (new_run && std::max(reported_id, p.desired_run_id) == INT32_MAX)
      throw std::invalid_argument("process '" + p.name + "' on " + p.host +
                                  ": its deputy reports run id " + std::to_string(INT32_MAX) +
                                  ", the last there is; restart that deputy for a new run");
  }
  bool found = false;
  for (auto& p : processes_) {
    if (!p.in_manifest || (target != "all" && p.name != target)) continue;
    found = true;
    const int32_t reported_id = p.reported ? p.reported->run_id : -1;
    switch (command) {
      case Command::kStop:
        p.desired_run = false;
        break;
      case Command::kStart:
        p.desired_run = true;
        if (p.reported && is_down_for_good(p.reported->state))
          p.desired_run_id = std::max(reported_id, p.desired_run_id) + 1;
        break;
      case Command::kRestart:
        p.desired_run = true;
        p.desired_run_id = std::max(reported_id, p.desired_run_id) + 1;
        break;
    }
  }
  if (!found) {
    std::string known;
    for (const auto& m : manifest_.process()) known += " " + m.name();
    throw std::invalid_argument("no process '" + target + "' in the manifest (processes:" + known +
                                "; or all)");
  }
}

std::vector<deputy_orders_t> Sheriff::orders(bool only_heard_hosts) const {
  std::vector<deputy_orders_t> out;
  for (const auto& h : hosts_) {
    if (only_heard_hosts && h.last_status_ns < 0) continue;
    deputy_orders_t o{};
    o.host = h.name;
    o.sheriff = options_.id;
    o.manifest_name = manifest_.name();
    o.manifest_text = manifest_text_;
    o.lcm_url = options_.lcm_url;
    for (const auto& m : manifest_.process()) {
      if (m.host() != h.name) continue;
      const ProcessView* view = find(h.name, m.name());
      deputy_process_order_t p{};
      p.name = m.name();
      p.exec = m.exec();
      p.args = expand_args(m, options_.params);
      p.num_args = static_cast<int32_t>(p.args.size());
      p.run = view->desired_run;
      p.run_id = view->desired_run_id;
      p.allow_exit = m.allow_exit();
      o.processes.push_back(p);
    }
    o.num_processes = static_cast<int32_t>(o.processes.size());
    o.start_scheduler = options_.start_scheduler && o.num_processes > 0;
    out.push_back(std::move(o));
  }
  return out;
}

bool Sheriff::converged(int64_t now_ns, std::vector<std::string>* waiting_for) const {
  std::vector<std::string> waiting;
  for (const auto& h : hosts_) {
    bool needed = false;
    for (const auto& p : processes_) needed = needed || (p.host == h.name && p.in_manifest);
    if (needed && !host_alive(h, now_ns))
      waiting.push_back("host " + h.name + ": no deputy heard" +
                        (h.last_status_ns >= 0 ? " recently" : ""));
  }
  for (const auto& p : processes_) {
    const bool scheduler = !p.in_manifest && p.name == kScheduler;
    if (!p.in_manifest && !scheduler) continue;
    const HostView* h = find_host(p.host);
    if (h == nullptr || !host_alive(*h, now_ns)) continue;  // reported above
    bool allow_exit = false;
    for (const auto& m : manifest_.process())
      allow_exit = allow_exit || (m.name() == p.name && m.allow_exit());
    std::string problem;
    const auto& r = p.reported;
    if (p.desired_run || scheduler) {
      if (!r)
        problem = "not started yet";
      else if (!(r->state == "running" || (allow_exit && r->state == "finished")))
        problem = printable(r->state, kStateMax) +
                  (r->reason.empty() ? "" : " (" + printable(r->reason, kReasonMax) + ")");
      else if (p.desired_run_id >= 0 && r->run_id < p.desired_run_id)
        problem = "restart pending";
    } else if (r && !is_stopped(r->state)) {
      problem = printable(r->state, kStateMax);
    }
    if (!problem.empty())
      waiting.push_back(printable(p.name, kNameMax) + "@" + printable(p.host, kNameMax) + ": " +
                        problem);
  }
  if (waiting_for != nullptr) *waiting_for = waiting;
  return waiting.empty();
}

std::vector<std::string> Sheriff::host_events(int64_t now_ns) {
  std::vector<std::string> events;
  for (auto& h : hosts_) {
    const bool alive = host_alive(h, now_ns);
    if (!alive && !h.lost && h.last_status_ns >= 0) {
      h.lost = true;
      events.push_back("host " + h.name + ": deputy lost (no status for " +
                       seconds_1dp(static_cast<double>(now_ns - h.last_status_ns) * 1e-9) + " s)");
    } else if (alive && h.lost) {
      h.lost = false;
      events.push_back("host " + h.name + ": deputy back (pid " + std::to_string(h.deputy_pid) +
                       ")");
    }
  }
  return events;
}

bool Sheriff::all_hosts_heard() const {
  for (const auto& h : hosts_) {
    bool needed = false;
    for (const auto& p : processes_) needed = needed || (p.host == h.name && p.in_manifest);
    if (needed && h.last_status_ns < 0) return false;
  }
  return true;
}

std::string Sheriff::table(int64_t now_ns) const {
  char line[512];
  std::string out;
  std::snprintf(line, sizeof line, "%-10s %-12s %-9s %-4s %7s %4s %6s %7s %8s  %s\n", "HOST",
                "PROCESS", "STATE", "WANT", "PID", "RST", "CPU%", "RSS MB", "UP s", "REASON");
  out += line;
  for (const auto& h : hosts_) {
    bool any = false;
    for (const auto& p : processes_) any = any || p.host == h.name;
    if (!any) continue;
    const bool alive = host_alive(h, now_ns);
    const std::string host = printable(h.name, kNameMax);
    if (alive && h.offset_plus_delay_us != 0) {
      std::snprintf(line, sizeof line,
                    "%s: deputy pid %d, load %.2f, clock offset + delay %+.1f ms\n", host.c_str(),
                    h.deputy_pid, static_cast<double>(h.load),
                    static_cast<double>(h.offset_plus_delay_us) * 1e-3);
      out += line;
    }
    if (!alive) {
      out += host + ": " +
             (h.last_status_ns < 0
                  ? std::string("no deputy heard (run: ephor-deputy --host ") + host + ")"
                  : "DEPUTY LOST, no status for " +
                        seconds_1dp(static_cast<double>(now_ns - h.last_status_ns) * 1e-9) +
                        " s; last known:") +
             "\n";
    }
    for (const auto& p : processes_) {
      if (p.host != h.name) continue;
      const bool scheduler = !p.in_manifest && p.name == kScheduler;
      const char* want = p.in_manifest ? (p.desired_run ? "run" : "stop") : scheduler ? "run" : "-";
      const std::string name = printable(p.name, kNameMax);
      if (!p.reported) {
        std::snprintf(line, sizeof line, "%-10s %-12s %-9s %-4s %7s %4s %6s %7s %8s  %s\n",
                      host.c_str(), name.c_str(), "-", want, "-", "-", "-", "-", "-",
                      "not reported by the deputy");
      } else {
        const auto& r = *p.reported;
        std::snprintf(
            line, sizeof line, "%-10s %-12s %-9s %-4s %7d %4d %6.1f %7.1f %8.1f  %s\n",
            host.c_str(), name.c_str(), printable(r.state, kStateMax).c_str(), want, r.pid,
            r.restarts, static_cast<double>(r.cpu_percent), static_cast<double>(r.rss_bytes) / 1e6,
            static_cast<double>(r.uptime_us) * 1e-6, printable(r.reason, kReasonMax).c_str());
      }
      out += line;
    }
  }
  return out;
}

}  // namespace ephor::sheriff
