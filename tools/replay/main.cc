// ephor-replay: deterministic replay of a logged run through real ephor
// processes (tools/ephor replay). Starts the processes under test on a
// private LCM port (vision with --on-frame: one job per frame), feeds the
// logged input channels in log order, and after each logged frame waits for
// the output of the same capture utime before feeding the next, so every
// process sees every frame, in order, one at a time: two replays of one log
// give identical outputs. The outputs are written to an LCM log (--out),
// each stamped with the log timestamp of the frame it answers and with the
// fields that depend on when the replay ran (header.utime, processing_us)
// set to 0: two replays of one log give byte-identical files.
//
//   ephor-replay LOG --procs vision,worldmodel [--out FILE] [--timeout-s 2]
//                [--only-processed] [--attach] [--lcm-url URL]
//                [--vision-arg ARG ...] [--worldmodel-arg ARG ...]
//
// A frame the world model must ignore (its utime does not increase: a
// duplicated or out-of-order frame) gets no OBJECTS: the replay then waits
// for vision's BLOBS of it only. Exit status: 0 when every frame was
// answered, 3 when some timed out (counted in the summary), 1 on an error
// (unreadable log, a process that would not start or died).

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <lcm/lcm-cpp.hpp>

#include "common/launch/process_group.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/runtime/channels.h"
#include "common/runtime/process_args.h"
#include "ephor/task_register_t.hpp"
#include "tools/replay/replay_plan.h"

namespace {

using ephor::replay::ReplayPlan;
using Clock = std::chrono::steady_clock;

// Outputs heard on the bus (LCM thread) and process registrations.
class Outputs {
 public:
  explicit Outputs(const ReplayPlan& plan) : plan_(plan) {}

  static void on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                         Outputs* self) {
    self->handle(rbuf, channel);
  }

  struct Record {
    int step = 0;  // index of the fed frame it arrived after
    std::string channel;
    std::vector<uint8_t> data;  // normalised
  };

  void set_step(int step) {
    std::lock_guard<std::mutex> lock(mutex_);
    step_ = step;
  }
  int count(const std::string& channel, int64_t utime) {
    std::lock_guard<std::mutex> lock(mutex_);
    return counts_[{channel, utime}];
  }
  int64_t max_final_utime() {
    std::lock_guard<std::mutex> lock(mutex_);
    return max_final_utime_;
  }
  // Waits until `pred` (called under the lock) is true or `deadline` passes.
  template <class Pred>
  bool wait(Clock::time_point deadline, Pred pred) {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_until(lock, deadline, pred);
  }
  int count_locked(const std::string& channel, int64_t utime) {
    const auto it = counts_.find({channel, utime});
    return it == counts_.end() ? 0 : it->second;
  }
  bool registered(const std::string& process) {
    std::lock_guard<std::mutex> lock(mutex_);
    return registered_.count(process) != 0;
  }
  std::vector<Record> records() {
    std::lock_guard<std::mutex> lock(mutex_);
    return records_;
  }
  int bad_outputs() {
    std::lock_guard<std::mutex> lock(mutex_);
    return bad_outputs_;
  }

 private:
  void handle(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    const int size = static_cast<int>(rbuf->data_size);
    std::lock_guard<std::mutex> lock(mutex_);
    if (channel == ephor::channels::kTaskRegister) {
      ephor::task_register_t m;
      if (m.decode(rbuf->data, 0, size) == size) registered_.insert(m.process);
      return;
    }
    const auto utime = ephor::replay::message_utime(rbuf->data, size);
    try {
      if (!utime) throw std::invalid_argument(channel + ": message too short");
      records_.push_back(
          {step_, channel, ephor::replay::normalised_output(channel, rbuf->data, size)});
    } catch (const std::exception& e) {
      if (++bad_outputs_ <= 5) std::fprintf(stderr, "[replay] ignoring output: %s\n", e.what());
      return;
    }
    ++counts_[{channel, *utime}];
    if (channel == plan_.final_channel) max_final_utime_ = std::max(max_final_utime_, *utime);
    cv_.notify_all();
  }

  const ReplayPlan& plan_;
  std::mutex mutex_;
  std::condition_variable cv_;
  int step_ = 0;
  std::map<std::pair<std::string, int64_t>, int> counts_;
  std::set<std::string> registered_;
  std::vector<Record> records_;
  int64_t max_final_utime_ = INT64_MIN;
  int bad_outputs_ = 0;
};

std::unique_ptr<lcm::LogFile> open_log(const std::string& path) {
  auto log = std::make_unique<lcm::LogFile>(path, "r");
  if (!log->good()) throw std::runtime_error("cannot read LCM log '" + path + "'");
  return log;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ephor-replay: feed a logged run to real processes, one frame at a time"};
  std::string log_path, procs = "vision,worldmodel", out_path, url;
  double timeout_s = 2.0;
  bool only_processed = false, attach = false;
  std::vector<std::string> vision_args, worldmodel_args;
  app.add_option("log", log_path, "LCM log of a run (lcm-logger, tools/ephor log record)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--procs", procs, "processes to replay through, comma-separated");
  app.add_option("--out", out_path, "write the outputs to this LCM log");
  app.add_option("--timeout-s", timeout_s, "longest wait for one frame's output, s")
      ->check(CLI::Range(0.01, 600.0));
  app.add_flag("--only-processed", only_processed,
               "feed only the frames the logged run answered (with the last process's output "
               "in the log), to reproduce its outputs");
  app.add_flag("--attach", attach,
               "use processes already running on --lcm-url instead of starting them (their "
               "state is not fresh: outputs may differ from a replay that starts them)");
  app.add_option("--lcm-url", url,
                 "LCM URL (default: a private port for the started processes; with --attach, "
                 "LCM_DEFAULT_URL or the default)");
  app.add_option("--vision-arg", vision_args, "extra flag for ephor-vision (repeat)")
      ->allow_extra_args(false);
  app.add_option("--worldmodel-arg", worldmodel_args, "extra flag for ephor-worldmodel (repeat)")
      ->allow_extra_args(false);
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;

  std::unique_ptr<ephor::launcher::ProcessGroup> group;
  std::atomic<bool> polling{true};
  std::thread poller;
  std::mutex exits_mutex;
  std::vector<ephor::launcher::ExitInfo> exits;
  const auto stop_children = [&] {
    polling = false;
    if (poller.joinable()) poller.join();
    if (group) group->stop_all(std::chrono::milliseconds(3000));
  };
  int rc = 0;
  try {
    const ReplayPlan plan = ephor::replay::make_replay_plan(procs);

    // Pass 1: count the frames; the answered ones for --only-processed.
    std::set<int64_t> answered;
    int64_t logged_frames = 0;
    {
      auto log = open_log(log_path);
      while (const lcm::LogEvent* ev = log->readNextEvent()) {
        if (ev->channel == plan.frame_channel) ++logged_frames;
        if (only_processed && ev->channel == plan.final_channel) {
          if (auto u = ephor::replay::message_utime(ev->data, ev->datalen)) answered.insert(*u);
        }
      }
    }
    if (logged_frames == 0) {
      throw std::runtime_error("log '" + log_path + "' has no " + plan.frame_channel +
                               " messages to replay");
    }
    if (only_processed && answered.empty()) {
      throw std::runtime_error("--only-processed: log '" + log_path + "' has no " +
                               plan.final_channel + " messages");
    }

    if (url.empty()) {
      url = attach ? ephor::resolve_lcm_url("")
                   : "udpm://239.255.76.67:" + std::to_string(7700 + getpid() % 2000) +
                         "?ttl=0&recv_buf_size=16777216";
    }
    lcm::LCM lcm(url);
    if (!lcm.good()) throw std::runtime_error("cannot open LCM on '" + url + "'");
    Outputs outputs(plan);
    for (const auto& ch : plan.output_channels)
      lcm.subscribeFunction<Outputs*>(ch, &Outputs::on_message, &outputs);
    lcm.subscribeFunction<Outputs*>(ephor::channels::kTaskRegister, &Outputs::on_message, &outputs);
    std::atomic<bool> handling{true};
    std::thread handler([&] {
      while (handling) lcm.handleTimeout(50);
    });

    if (!attach) {
      const char* bin_dir = std::getenv("EPHOR_BIN");
      std::string dir = bin_dir != nullptr ? bin_dir : "";
      if (dir.empty()) {
        // Beside this binary (build/bin).
        char self[4096];
        const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
        if (n > 0) {
          self[n] = '\0';
          dir = std::string(self).substr(0, std::string(self).rfind('/'));
        }
      }
      group = std::make_unique<ephor::launcher::ProcessGroup>(
          [](const std::string& name, const std::string& line) {
            std::fprintf(stderr, "[%s] %s\n", name.c_str(), line.c_str());
          });
      for (const auto& p : plan.processes) {
        ephor::launcher::ProcessSpec spec;
        spec.name = p.name;
        spec.path = ephor::launcher::resolve_executable(p.exec, dir);
        if (spec.path.empty()) throw std::runtime_error("cannot find " + p.exec + " in " + dir);
        spec.args = p.replay_args;
        for (const char* a : {"--no-mlock", "--name"}) spec.args.emplace_back(a);
        spec.args.push_back(p.name);
        spec.args.push_back("--lcm-url");
        spec.args.push_back(url);
        const auto& extra = p.name == "vision" ? vision_args : worldmodel_args;
        spec.args.insert(spec.args.end(), extra.begin(), extra.end());
        spec.env = {{"EPHOR_HOST", "replay"}};
        group->start(spec);
      }
      poller = std::thread([&] {
        while (polling) {
          auto e = group->poll(50);
          if (!e.empty()) {
            std::lock_guard<std::mutex> lock(exits_mutex);
            exits.insert(exits.end(), e.begin(), e.end());
          }
        }
      });
      const auto ready_by = Clock::now() + std::chrono::seconds(15);
      for (const auto& p : plan.processes) {
        while (!outputs.registered(p.name)) {
          {
            std::lock_guard<std::mutex> lock(exits_mutex);
            if (!exits.empty()) {
              throw std::runtime_error(exits[0].name + " " + exits[0].describe() +
                                       " before the replay started");
            }
          }
          if (Clock::now() > ready_by) {
            throw std::runtime_error(p.name + " did not register its task within 15 s");
          }
          std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
      }
    }

    // Pass 2: feed the inputs in log order, one frame at a time.
    const bool has_vision = plan.processes.front().name == "vision";
    const bool has_worldmodel = plan.processes.back().name == "worldmodel";
    int step = 0;
    int64_t fed = 0, skipped = 0, timeouts = 0, ignored_by_worldmodel = 0;
    std::vector<int64_t> step_timestamp;  // log timestamp of each fed frame
    auto log = open_log(log_path);
    while (const lcm::LogEvent* ev = log->readNextEvent()) {
      if (!plan.is_input(ev->channel)) continue;
      if (ev->channel != plan.frame_channel) {
        lcm.publish(ev->channel, ev->data, static_cast<unsigned int>(ev->datalen));
        continue;
      }
      const auto utime = ephor::replay::message_utime(ev->data, ev->datalen);
      if (!utime || (only_processed && answered.count(*utime) == 0)) {
        ++skipped;
        continue;
      }
      {
        std::lock_guard<std::mutex> lock(exits_mutex);
        if (!exits.empty()) {
          throw std::runtime_error(exits[0].name + " " + exits[0].describe() + " at frame " +
                                   std::to_string(fed));
        }
      }
      outputs.set_step(step);
      step_timestamp.push_back(ev->timestamp);
      // The world model ignores a frame whose time does not increase: then
      // only vision's answer can be waited for.
      const bool final_expected = !has_worldmodel || *utime > outputs.max_final_utime();
      if (!final_expected) ++ignored_by_worldmodel;
      const std::string& awaited =
          final_expected ? plan.final_channel : std::string(ephor::channels::kBlobs);
      const int before = outputs.count(awaited, *utime);
      lcm.publish(ev->channel, ev->data, static_cast<unsigned int>(ev->datalen));
      ++fed;
      const auto deadline =
          Clock::now() + std::chrono::microseconds(static_cast<int64_t>(timeout_s * 1e6));
      bool answered_now = true;
      if (final_expected || has_vision) {
        answered_now =
            outputs.wait(deadline, [&] { return outputs.count_locked(awaited, *utime) > before; });
      }
      if (!answered_now) {
        ++timeouts;
        if (timeouts <= 5) {
          std::fprintf(stderr, "[replay] no %s for frame utime %lld within %.2f s\n",
                       awaited.c_str(), static_cast<long long>(*utime), timeout_s);
        }
      }
      ++step;
    }
    handling = false;
    handler.join();
    stop_children();

    std::map<std::string, int> per_channel;
    const auto records = outputs.records();
    for (const auto& r : records) ++per_channel[r.channel];
    if (!out_path.empty()) {
      lcm::LogFile out(out_path, "w");
      if (!out.good()) throw std::runtime_error("cannot write '" + out_path + "'");
      // Grouped by step, in pipeline order within a step (arrival order kept).
      for (int s = 0; s < step; ++s) {
        for (const auto& ch : plan.output_channels) {
          for (const auto& r : records) {
            if (r.step != s || r.channel != ch) continue;
            lcm::LogEvent e{};
            e.timestamp = step_timestamp[static_cast<size_t>(s)];
            e.channel = r.channel;
            e.datalen = static_cast<int32_t>(r.data.size());
            e.data = const_cast<uint8_t*>(r.data.data());
            if (out.writeEvent(&e) != 0) throw std::runtime_error("writing '" + out_path + "'");
          }
        }
      }
    }
    std::string counts;
    for (const auto& ch : plan.output_channels)
      counts += ", " + std::to_string(per_channel[ch]) + " " + ch;
    std::fprintf(stderr,
                 "[replay] %s through %s: %lld of %lld %s frames fed (%lld skipped), %lld with "
                 "no OBJECTS expected (time not increasing); outputs%s; %lld timeouts%s%s\n",
                 log_path.c_str(), procs.c_str(), static_cast<long long>(fed),
                 static_cast<long long>(logged_frames), plan.frame_channel.c_str(),
                 static_cast<long long>(skipped), static_cast<long long>(ignored_by_worldmodel),
                 counts.c_str(), static_cast<long long>(timeouts), out_path.empty() ? "" : " -> ",
                 out_path.c_str());
    if (timeouts > 0) rc = 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "[replay] error: %s\n", e.what());
    stop_children();
    return 1;
  }
  return rc;
}
