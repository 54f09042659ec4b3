#include "common/launch/deputy_core.h"

#include <algorithm>
#include <chrono>
#include <climits>
#include <stdexcept>

#include "common/time/clock.h"

namespace ephor::deputy {

DeputyCore::DeputyCore(RestartPolicy policy, std::string bin_dir,
                       launcher::ProcessGroup::LineHandler on_line)
    : policy_(policy), bin_dir_(std::move(bin_dir)), table_(policy), group_(std::move(on_line)) {}

DeputyCore::~DeputyCore() { stop_all(); }

void DeputyCore::apply(const std::vector<ProcessOrder>& orders) { table_.apply(orders, mono_ns()); }

void DeputyCore::send(const Action& action, std::vector<DeputyEvent>& events) {
  if (!group_.signal(action.pid, action.signal)) return;  // exited meanwhile: reaped next
  DeputyEvent e;
  e.kind = DeputyEvent::Kind::kSignalled;
  e.name = action.name;
  e.pid = action.pid;
  e.signal = action.signal;
  e.at_ns = mono_ns();
  if (const ProcessRow* row = table_.find(action.name)) {
    e.run_id = row->run_id;
    e.state = row->state;
    e.reason = row->reason;
  }
  events.push_back(std::move(e));
}

void DeputyCore::act(std::vector<DeputyEvent>& events) {
  for (const auto& a : table_.step(mono_ns())) {
    if (a.kind == Action::Kind::kSignal) {
      send(a, events);
      continue;
    }
    const ProcessRow* row = table_.find(a.name);
    if (row == nullptr) continue;
    const ProcessOrder order = row->order;
    DeputyEvent e;
    e.name = a.name;
    const std::string path = launcher::resolve_executable(order.exec, bin_dir_);
    try {
      if (path.empty())
        throw std::runtime_error("executable '" + order.exec + "' not found in " + bin_dir_ +
                                 " or $PATH");
      e.pid = group_.start({a.name, path, order.args, order.env, order.allow_exit});
      e.at_ns = mono_ns();
      table_.started(a.name, e.pid, e.at_ns);
      start_sequence_[e.pid] = starts_++;
      e.kind = DeputyEvent::Kind::kStarted;
      e.path = path;
    } catch (const std::exception& ex) {
      e.at_ns = mono_ns();
      table_.start_failed(a.name, ex.what());
      e.kind = DeputyEvent::Kind::kStartFailed;
    }
    row = table_.find(a.name);
    e.run_id = row->run_id;
    e.state = row->state;
    e.reason = row->reason;
    events.push_back(std::move(e));
  }
}

void DeputyCore::take_exits(const std::vector<launcher::ExitInfo>& exits,
                            std::vector<DeputyEvent>& events) {
  for (const auto& x : exits) {
    DeputyEvent e;
    e.at_ns = mono_ns();
    table_.exited(x.pid, x.signaled, x.code, x.describe(), e.at_ns);
    start_sequence_.erase(x.pid);
    e.kind = DeputyEvent::Kind::kExited;
    e.name = x.name;
    e.pid = x.pid;
    e.exit = x;
    const ProcessRow* row = table_.find(x.name);
    e.in_table = row != nullptr;
    if (row != nullptr) {
      e.run_id = row->run_id;
      e.state = row->state;
      e.reason = row->reason;
    }
    events.push_back(std::move(e));
  }
}

int DeputyCore::wait_ms(int timeout_ms) const {
  const int64_t deadline = table_.next_deadline_ns();
  if (deadline == INT64_MAX) return std::max(timeout_ms, 0);
  // Rounded up: waking just before the deadline would only spin once more.
  const int64_t until_ms = (deadline - mono_ns() + 999'999) / 1'000'000;
  return static_cast<int>(std::clamp<int64_t>(until_ms, 0, std::max(timeout_ms, 0)));
}

std::vector<DeputyEvent> DeputyCore::poll(int timeout_ms) {
  std::vector<DeputyEvent> events;
  act(events);  // orders applied since the last call take effect now, not after the wait
  // Returned before any output is read, so that a wrapper prints "started
  // NAME" before NAME's first line.
  if (!events.empty()) return events;
  take_exits(group_.poll(wait_ms(timeout_ms)), events);
  act(events);
  return events;
}

std::vector<DeputyEvent> DeputyCore::stop_all() {
  std::vector<DeputyEvent> events;
  // Through the table, so its rows end "stopped" with the reason and it
  // sends the SIGKILLs after the grace time, as for a stop the orders ask.
  std::vector<ProcessOrder> stopped;
  for (const auto& r : table_.rows()) {
    if (r.forget) continue;  // already being stopped, then forgotten
    stopped.push_back(r.order);
    stopped.back().run = false;
  }
  table_.apply(stopped, mono_ns());
  auto actions = table_.step(mono_ns());
  // Newest first: what started first (a logger, the scheduler) hears the
  // others' last messages and stops last.
  auto sequence = [&](pid_t pid) {
    const auto it = start_sequence_.find(pid);
    return it == start_sequence_.end() ? uint64_t{0} : it->second;
  };
  std::stable_sort(actions.begin(), actions.end(), [&](const Action& a, const Action& b) {
    return sequence(a.pid) > sequence(b.pid);
  });
  for (const auto& a : actions)
    if (a.kind == Action::Kind::kSignal) send(a, events);

  auto stopping = [&] {
    for (const auto& r : table_.rows())
      if (r.state == ProcessState::kStopping) return true;
    return false;
  };
  while (stopping()) {
    take_exits(group_.poll(wait_ms(50)), events);
    for (const auto& a : table_.step(mono_ns()))
      if (a.kind == Action::Kind::kSignal) send(a, events);
  }
  // Every child is the table's, so none should be left; this also forwards
  // the last partial lines of output pipes a grandchild still holds open.
  take_exits(group_.stop_all(std::chrono::duration_cast<std::chrono::milliseconds>(
                 std::chrono::nanoseconds(policy_.stop_grace_ns))),
             events);
  return events;
}

}  // namespace ephor::deputy
