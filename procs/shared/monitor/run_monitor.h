#pragma once
// RunMonitor: scores a running shepherding system against the simulator's
// ground truth and summarises it (the `--summary` JSON of a headless run and
// the demo's status line). Pure: the process feeds it decoded messages.
//
// Id switches: each visible truth sheep is matched to the nearest tracked
// object (visible or obscured) of the same frame within `match_radius_mm`;
// when a truth sheep that was matched to object A is matched to object B,
// that is one id switch.

#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/runtime/rolling_stats.h"

namespace ephor::monitor {

struct TruthSheep {
  int32_t id = 0;
  double x_mm = 0, y_mm = 0;
  double u = 0, v = 0;  // true mark centre in the image, px
  bool visible = true;
  bool on_field = true;
};

struct Truth {
  int64_t utime = 0;  // frame capture time, us
  std::vector<TruthSheep> sheep;
  int32_t escapes = 0;
  int32_t saves = 0;
  double sim_time_s = 0;
};

struct TrackedObject {
  int32_t id = 0;
  bool visible = true;
  bool dead = false;
  double x_mm = 0, y_mm = 0;
  double u = 0, v = 0;
};

struct Summary {
  std::string scenario;
  double duration_s = 0;
  int sheep = 0;  // sheep on the field at the end
  int escapes = 0;
  int saves = 0;
  double vision_rate_hz = 0;
  double objects_rate_hz = 0;
  double latency_p50_ms = 0, latency_p99_ms = 0;
  int64_t latency_samples = 0;
  int64_t id_switches = 0;
  double position_error_px_rms = 0;  // visible, matched objects against truth
  int64_t deadline_misses = 0;
  bool rt = false;
  bool have_sched_status = false;
  int64_t arm_commands = 0;
  // Frame capture to each stage's output (p50, p99 in ms): where latency goes.
  struct Stage {
    std::string name;
    double p50_ms = 0, p99_ms = 0;
    int64_t samples = 0;
  };
  std::vector<Stage> stages;
  nlohmann::json to_json() const;
};

class RunMonitor {
 public:
  explicit RunMonitor(std::string scenario, double match_radius_mm = 40.0);

  void on_truth(const Truth& truth);
  // `published_us`: the message's header time (sender's publish time).
  void on_blobs(int64_t frame_utime, int64_t published_us, int64_t now_us);
  void on_objects(int64_t frame_utime, int64_t published_us,
                  const std::vector<TrackedObject>& objects, int64_t now_us);
  void on_arm_goal(int64_t source_frame_utime, int64_t published_us);
  // An arm command left comm at `sent_us`, planned from the frame captured at
  // `source_frame_utime` (both wall clock of this host, us).
  void on_arm_command(int64_t source_frame_utime, int64_t sent_us);
  void on_sched_status(bool rt, int64_t deadline_misses_total);

  Summary summary(int64_t now_us) const;
  std::string status_line(int64_t now_us) const;
  // What happened since the last call, one line each, for the log: every id
  // switch, with where the sheep was and what became of the object it had.
  std::vector<std::string> take_events();

 private:
  std::string scenario_;
  double match_radius_mm_;
  int64_t start_us_ = 0;
  std::deque<Truth> truths_;  // recent frames, for matching objects by capture time
  Truth last_truth_;
  std::map<int32_t, int32_t> matched_;  // truth id -> object id
  int64_t id_switches_ = 0;
  std::vector<std::string> events_;
  double err_sq_sum_ = 0;
  int64_t err_n_ = 0;
  std::deque<int64_t> blob_times_, object_times_;  // receive times in the last 5 s
  RollingStats latency_ms_{100000};
  RollingStats blobs_ms_{100000}, objects_ms_{100000}, goal_ms_{100000};
  int64_t arm_commands_ = 0;
  int64_t deadline_misses_ = 0;
  bool rt_ = false;
  bool have_sched_ = false;
};

}  // namespace ephor::monitor
