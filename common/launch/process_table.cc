#include "common/launch/process_table.h"

#include <signal.h>

#include <algorithm>
#include <climits>
#include <set>
#include <stdexcept>

namespace ephor::deputy {

bool ProcessOrder::same_command(const ProcessOrder& other) const {
  return exec == other.exec && args == other.args && env == other.env &&
         allow_exit == other.allow_exit;
}

const char* to_string(ProcessState state) {
  switch (state) {
    case ProcessState::kStopped:
      return "stopped";
    case ProcessState::kStarting:
      return "starting";
    case ProcessState::kRunning:
      return "running";
    case ProcessState::kStopping:
      return "stopping";
    case ProcessState::kBackoff:
      return "backoff";
    case ProcessState::kFailed:
      return "failed";
    case ProcessState::kFinished:
      return "finished";
  }
  return "?";
}

ProcessTable::ProcessTable(RestartPolicy policy) : policy_(policy) {}

ProcessRow* ProcessTable::find_mutable(const std::string& name) {
  for (auto& r : rows_)
    if (r.order.name == name) return &r;
  return nullptr;
}

const ProcessRow* ProcessTable::find(const std::string& name) const {
  for (const auto& r : rows_)
    if (r.order.name == name) return &r;
  return nullptr;
}

ProcessRow* ProcessTable::find_by_pid(pid_t pid) {
  for (auto& r : rows_)
    if (r.pid == pid && pid != 0 &&
        (r.state == ProcessState::kRunning || r.state == ProcessState::kStopping))
      return &r;
  return nullptr;
}

bool ProcessTable::wants_new_run(const ProcessRow& row) {
  if (row.run_id < 0) return false;  // never started: any start is a new run
  const bool new_id = row.order.run_id >= 0 && row.order.run_id != row.run_id;
  return new_id || !row.order.same_command(row.started_as);
}

void ProcessTable::set_state(ProcessRow& row, ProcessState state, std::string reason) {
  if (row.state != state || row.reason != reason) ++version_;
  row.state = state;
  row.reason = std::move(reason);
}

void ProcessTable::apply(const std::vector<ProcessOrder>& orders, int64_t now_ns) {
  (void)now_ns;
  std::set<std::string> names;
  for (const auto& o : orders)
    if (!names.insert(o.name).second)
      throw std::invalid_argument("orders name process '" + o.name + "' twice");

  std::vector<ProcessRow> next;
  for (const auto& o : orders) {
    ProcessRow* old = find_mutable(o.name);
    ProcessRow row;
    if (old != nullptr) {
      row = std::move(*old);
      old->order.name.clear();  // moved out; not carried over below
    }
    const bool was_run = old != nullptr && row.order.run;
    const bool changed = old == nullptr || was_run != o.run || row.order.run_id != o.run_id ||
                         !row.order.same_command(o);
    if (changed) ++version_;  // the desired state is part of the status
    row.order = o;
    row.forget = false;
    if (row.run_id < 0) row.started_as = o;
    // A process that is down for good comes back when the orders ask anew:
    // stop then start, a new run_id, or a new command line.
    const bool down = row.state == ProcessState::kFailed || row.state == ProcessState::kFinished;
    if (down && o.run && (!was_run || wants_new_run(row))) {
      row.crashes_in_row = 0;
      set_state(row, ProcessState::kStopped, row.reason);
    }
    if (row.state == ProcessState::kBackoff && !o.run) {
      row.crashes_in_row = 0;
      set_state(row, ProcessState::kStopped, "stopped by orders (" + row.reason + ")");
    }
    next.push_back(std::move(row));
  }
  // Processes no longer ordered: stop the running ones, then forget them.
  for (auto& r : rows_) {
    if (r.order.name.empty()) continue;
    if (r.state == ProcessState::kRunning || r.state == ProcessState::kStopping ||
        r.state == ProcessState::kStarting) {
      r.order.run = false;
      r.forget = true;
      next.push_back(std::move(r));
    }
    ++version_;
  }
  rows_ = std::move(next);
}

void ProcessTable::started(const std::string& name, pid_t pid, int64_t now_ns) {
  ProcessRow* r = find_mutable(name);
  if (r == nullptr || r->state != ProcessState::kStarting) return;
  r->pid = pid;
  r->started_ns = now_ns;  // exit_code / exit_signal keep the last exit
  set_state(*r, ProcessState::kRunning,
            r->crash_restart ? "restarted after crash: " + r->last_crash : "started");
  r->crash_restart = false;
}

void ProcessTable::start_failed(const std::string& name, const std::string& reason) {
  ProcessRow* r = find_mutable(name);
  if (r == nullptr || r->state != ProcessState::kStarting) return;
  r->pid = 0;
  set_state(*r, ProcessState::kFailed, reason);
}

void ProcessTable::exited(pid_t pid, bool signaled, int code, const std::string& description,
                          int64_t now_ns) {
  ProcessRow* r = find_by_pid(pid);
  if (r == nullptr) return;
  r->pid = 0;
  r->exit_code = signaled ? -1 : code;
  r->exit_signal = signaled ? code : 0;
  if (r->state == ProcessState::kStopping) {
    const std::string name = r->order.name;
    set_state(*r, ProcessState::kStopped, "stopped: " + description);
    if (r->forget)
      rows_.erase(std::remove_if(rows_.begin(), rows_.end(),
                                 [&](const ProcessRow& x) { return x.order.name == name; }),
                  rows_.end());
    return;
  }
  if (!signaled && code == 0 && r->started_as.allow_exit) {
    r->crashes_in_row = 0;
    set_state(*r, ProcessState::kFinished, "finished: " + description);
    return;
  }
  r->last_crash = description;
  if (now_ns - r->started_ns >= policy_.stable_time_ns) r->crashes_in_row = 0;
  ++r->crashes_in_row;
  if (r->crashes_in_row > policy_.max_restarts) {
    set_state(*r, ProcessState::kFailed,
              "gave up after " + std::to_string(r->crashes_in_row) + " crashes in a row; last " +
                  description);
    return;
  }
  int64_t delay = policy_.first_delay_ns;
  for (int i = 1; i < r->crashes_in_row && delay < policy_.max_delay_ns; ++i) delay *= 2;
  delay = std::min(delay, policy_.max_delay_ns);
  r->next_start_ns = now_ns + delay;
  set_state(*r, ProcessState::kBackoff, "crashed: " + description);
}

void ProcessTable::begin_stop(ProcessRow& row, int64_t now_ns, std::vector<Action>& actions,
                              const std::string& reason) {
  actions.push_back({Action::Kind::kSignal, row.order.name, row.pid, SIGTERM});
  row.kill_at_ns = now_ns + policy_.stop_grace_ns;
  row.kill_sent = false;
  set_state(row, ProcessState::kStopping, reason);
}

std::vector<Action> ProcessTable::step(int64_t now_ns) {
  std::vector<Action> actions;
  for (auto& r : rows_) {
    const bool new_run = wants_new_run(r);
    switch (r.state) {
      case ProcessState::kRunning:
        if (!r.order.run)
          begin_stop(r, now_ns, actions, "stopping (ordered)");
        else if (new_run)
          begin_stop(r, now_ns, actions, "restarting (ordered)");
        break;
      case ProcessState::kStopping:
        if (!r.kill_sent && now_ns >= r.kill_at_ns) {
          actions.push_back({Action::Kind::kSignal, r.order.name, r.pid, SIGKILL});
          r.kill_sent = true;
          set_state(r, ProcessState::kStopping, "did not stop within the grace time: SIGKILL");
        }
        break;
      case ProcessState::kBackoff:
      case ProcessState::kStopped: {
        const bool due = r.state == ProcessState::kStopped ||
                         (r.order.run && (new_run || now_ns >= r.next_start_ns));
        if (!r.order.run || !due) break;
        r.crash_restart = r.state == ProcessState::kBackoff && !new_run;
        if (r.crash_restart) ++r.restarts;
        r.started_as = r.order;
        r.run_id = r.order.run_id >= 0 ? r.order.run_id : std::max(r.run_id, 0);
        set_state(r, ProcessState::kStarting, r.reason);
        actions.push_back({Action::Kind::kStart, r.order.name, 0, 0});
        break;
      }
      case ProcessState::kStarting:
      case ProcessState::kFailed:
      case ProcessState::kFinished:
        break;
    }
  }
  return actions;
}

int64_t ProcessTable::next_deadline_ns() const {
  int64_t t = INT64_MAX;
  for (const auto& r : rows_) {
    if (r.state == ProcessState::kBackoff && r.order.run) t = std::min(t, r.next_start_ns);
    if (r.state == ProcessState::kStopping && !r.kill_sent) t = std::min(t, r.kill_at_ns);
  }
  return t;
}

}  // namespace ephor::deputy
