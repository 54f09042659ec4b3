#include "tests/integration/harness.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <stdexcept>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "common/time/clock.h"

namespace ephor::testing {

bool wait_until(const std::function<bool()>& pred, std::chrono::milliseconds timeout) {
  const int64_t deadline = mono_ns() + static_cast<int64_t>(timeout.count()) * 1'000'000;
  while (true) {
    if (pred()) return true;
    if (mono_ns() >= deadline) return pred();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

ChannelGap longest_gap_in_log(const std::string& log_path, const std::string& channel) {
  ChannelGap g;
  lcm::LogFile log(log_path, "r");
  if (!log.good()) throw std::runtime_error("cannot read the LCM log " + log_path);
  int64_t first = -1, last = -1;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    if (first < 0) first = e->timestamp;
    if (e->channel != channel) continue;
    const double gap_s = static_cast<double>(e->timestamp - last) * 1e-6;
    if (last >= 0 && gap_s > g.longest_s) {
      g.longest_s = gap_s;
      g.at_s = static_cast<double>(last - first) * 1e-6;
    }
    last = e->timestamp;
    ++g.count;
  }
  return g;
}

int launched_pid(const Processes& p, const std::string& launcher, const std::string& process) {
  const std::string key = "started " + process + " (pid ";
  int pid = 0;
  for (const std::string& line : p.lines(launcher)) {
    const auto at = line.find(key);
    if (at != std::string::npos) pid = std::atoi(line.c_str() + at + key.size());
  }
  return pid;
}

double kill_and_await_restart(const Processes& p, const std::string& launcher,
                              const std::string& process, std::chrono::milliseconds timeout) {
  const int victim = launched_pid(p, launcher, process);
  if (victim <= 0 || kill(victim, SIGKILL) != 0) return -1.0;
  const int64_t t0 = mono_ns();
  const bool restarted = wait_until(
      [&] {
        const int pid = launched_pid(p, launcher, process);
        return pid > 0 && pid != victim;
      },
      timeout);
  return restarted ? static_cast<double>(mono_ns() - t0) * 1e-9 : -2.0;
}

struct ChannelCounter::Impl {
  explicit Impl(const std::string& url) : lcm(url) {}
  lcm::LCM lcm;
  mutable std::mutex mutex;
  std::map<std::string, int64_t> counts;
  std::atomic<bool> running{true};
  std::thread thread;
};

ChannelCounter::ChannelCounter(const std::string& url, const std::vector<std::string>& channels)
    : impl_(std::make_unique<Impl>(url)) {
  if (!impl_->lcm.good()) throw std::runtime_error("ChannelCounter: no LCM at " + url);
  for (const std::string& channel : channels) {
    impl_->counts[channel] = 0;
    impl_->lcm.subscribeFunction(
        channel,
        +[](const lcm::ReceiveBuffer*, const std::string& ch, Impl* impl) {
          std::lock_guard<std::mutex> lock(impl->mutex);
          ++impl->counts[ch];
        },
        impl_.get());
  }
  impl_->thread = std::thread([impl = impl_.get()] {
    while (impl->running) impl->lcm.handleTimeout(50);
  });
}

ChannelCounter::~ChannelCounter() {
  impl_->running = false;
  impl_->thread.join();
}

int64_t ChannelCounter::count(const std::string& channel) const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  const auto it = impl_->counts.find(channel);
  return it == impl_->counts.end() ? 0 : it->second;
}

bool ChannelCounter::reached(const std::map<std::string, int64_t>& at_least) const {
  for (const auto& [channel, n] : at_least)
    if (count(channel) < n) return false;
  return true;
}

std::map<std::string, double> kill_each_in_turn(const Processes& p, const std::string& launcher,
                                                const std::vector<std::string>& victims,
                                                const ChannelCounter& heard,
                                                const std::map<std::string, int64_t>& resume,
                                                std::chrono::milliseconds restart_timeout,
                                                std::chrono::milliseconds flowing_timeout) {
  std::map<std::string, double> restart_s_of;
  const int64_t first_ns = mono_ns();
  for (const std::string& name : victims) {
    std::map<std::string, int64_t> target;
    for (const auto& [channel, n] : resume) target[channel] = heard.count(channel) + n;
    const int64_t t0 = mono_ns();
    const double restart_s = kill_and_await_restart(p, launcher, name, restart_timeout);
    if (restart_s < 0.0) {
      ADD_FAILURE() << name << (restart_s < -1.5 ? " was not restarted" : " had no pid");
      break;
    }
    restart_s_of[name] = restart_s;
    const bool flowing = wait_until([&] { return heard.reached(target); }, flowing_timeout);
    std::fprintf(stderr,
                 "%s (killed %.1f s in): kill -9 -> running again %.3f s, flowing again %.1f s\n",
                 name.c_str(), static_cast<double>(t0 - first_ns) * 1e-9, restart_s,
                 static_cast<double>(mono_ns() - t0) * 1e-9);
    if (!flowing) {
      ADD_FAILURE() << "the system's outputs did not flow again after " << name << " was killed";
      break;
    }
  }
  return restart_s_of;
}

PacketLoss::PacketLoss(double probability)
    : rule_("INPUT -i lo -m statistic --mode random --probability " + std::to_string(probability) +
            " -j DROP") {
  if (std::system(("iptables -A " + rule_).c_str()) != 0)
    throw std::runtime_error("iptables could not add '" + rule_ +
                             "' (the statistic match and root are needed)");
}

PacketLoss::~PacketLoss() {
  if (std::system(("iptables -D " + rule_).c_str()) != 0)
    std::fprintf(stderr, "iptables could not remove '%s'\n", rule_.c_str());
}

std::map<std::string, int> arm_goal_starts(const std::vector<std::string>& launcher_lines) {
  std::map<std::string, int> started;
  for (const std::string& line : launcher_lines) {
    if (line.find("[arm ") == std::string::npos) continue;
    const auto at = line.find(" goal ");
    if (at == std::string::npos) continue;
    const auto colon = line.find(": ", at);
    if (colon == std::string::npos || line.find(" move ", colon) == std::string::npos) continue;
    ++started[line.substr(at + 6, colon - at - 6)];
  }
  return started;
}

void expect_clean_exit(const Processes& p, const std::string& name, const std::string& what) {
  bool seen = false;
  for (const auto& e : p.exits()) {
    if (e.name != name) continue;
    seen = true;
    EXPECT_EQ(e.code, 0) << name << " exited with status " << e.code
                         << ": a process of the run failed" << (what.empty() ? "" : " ") << what;
  }
  EXPECT_TRUE(seen) << name << " has not exited";
}

size_t expect_each_goal_once(const Processes& p, const std::string& launcher, size_t at_least) {
  const std::vector<std::string> lines = p.lines(launcher);
  const std::map<std::string, int> started = arm_goal_starts(lines);
  int from_before_restart = 0;  // commands a restarted arm refused (CommandLedger)
  for (const std::string& line : lines)
    from_before_restart += line.find("[arm ") != std::string::npos &&
                           line.find("before this arm started") != std::string::npos;
  std::fprintf(stderr,
               "the arm set off on %zu goals; a restarted arm refused %d transmissions of commands "
               "sent before it started\n",
               started.size(), from_before_restart);
  EXPECT_GE(started.size(), at_least) << "the arm was hardly sent anything";
  for (const auto& [goal, times] : started)
    EXPECT_EQ(times, 1) << "goal " << goal << ": the arm set off on it " << times << " times";
  return started.size();
}

double slowest_restart_s(const std::map<std::string, double>& restart_s_of) {
  double slowest = 0.0;
  for (const auto& [name, s] : restart_s_of) slowest = std::max(slowest, s);
  return slowest;
}

void expect_log_gaps_within(const std::string& log_path,
                            const std::vector<std::pair<std::string, double>>& bounds,
                            int min_messages) {
  for (const auto& [channel, bound_s] : bounds) {
    const ChannelGap g = longest_gap_in_log(log_path, channel);
    std::fprintf(stderr, "log: %d messages on %s, longest gap %.2f s at %.2f s (bound %.2f s)\n",
                 g.count, channel.c_str(), g.longest_s, g.at_s, bound_s);
    EXPECT_GE(g.count, min_messages) << channel;
    EXPECT_LT(g.longest_s, bound_s) << channel;
  }
}

std::string bin(const std::string& name) {
  const char* dir = std::getenv("EPHOR_BIN_DIR");
  if (dir == nullptr)
    throw std::runtime_error("EPHOR_BIN_DIR is not set (run the test through ctest)");
  return std::string(dir) + "/" + name;
}

std::string source_path(const std::string& relative) {
  const char* dir = std::getenv("EPHOR_SOURCE_DIR");
  if (dir == nullptr)
    throw std::runtime_error("EPHOR_SOURCE_DIR is not set (run the test through ctest)");
  return std::string(dir) + "/" + relative;
}

std::string write_temp_file(const std::string& name, const std::string& text) {
  static std::string dir = [] {
    char tmpl[] = "/tmp/ephor-test-XXXXXX";
    const char* d = mkdtemp(tmpl);
    if (d == nullptr) throw std::runtime_error("mkdtemp failed");
    return std::string(d);
  }();
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

Processes::Processes() {
  group_ = std::make_unique<launcher::ProcessGroup>(
      [this](const std::string& name, const std::string& line) {
        // Called from poller_ with mutex_ held.
        lines_[name].push_back(line);
        std::fprintf(stderr, "[%s] %s\n", name.c_str(), line.c_str());
      });
  poller_ = std::thread([this] {
    while (true) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!running_) break;
        auto e = group_->poll(0);
        exits_.insert(exits_.end(), e.begin(), e.end());
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  });
}

Processes::~Processes() { stop_all(); }

void Processes::start(const std::string& name, const std::string& exec,
                      const std::vector<std::string>& args,
                      const std::vector<std::pair<std::string, std::string>>& env) {
  std::lock_guard<std::mutex> lock(mutex_);
  pids_[name] = group_->start({name, exec, args, env, false});
}

void Processes::signal(const std::string& name, int sig) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = pids_.find(name);
  if (it != pids_.end()) kill(it->second, sig);
}

std::vector<std::string> Processes::lines(const std::string& name) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = lines_.find(name);
  return it == lines_.end() ? std::vector<std::string>{} : it->second;
}

bool Processes::has_line(const std::string& name, const std::string& text) const {
  for (const auto& l : lines(name))
    if (l.find(text) != std::string::npos) return true;
  return false;
}

std::vector<launcher::ExitInfo> Processes::exits() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return exits_;
}

bool Processes::exited(const std::string& name) const {
  for (const auto& e : exits())
    if (e.name == name) return true;
  return false;
}

void Processes::stop_all() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!running_) return;
    running_ = false;
  }
  if (poller_.joinable()) poller_.join();
  std::lock_guard<std::mutex> lock(mutex_);
  group_->stop_all(std::chrono::milliseconds(3000));
}

}  // namespace ephor::testing
