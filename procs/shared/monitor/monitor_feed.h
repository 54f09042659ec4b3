#pragma once
// MonitorFeed: ephor-monitor's LCM handlers without LCM. Each message is
// converted as the process takes it and handed to RunMonitor: out of main.cc
// so that the fuzz target monitor_feed_fuzz.cc runs what the process runs.
//
// Two things the handlers keep besides RunMonitor: the arm commands seen,
// by (sender, seq), because comm sends a command again until the arm
// acknowledges it and a retransmission is not a new command; and each
// host's last scheduler status, because the run is real-time only when every
// host is, and its deadline misses are the sum over hosts.

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <utility>

#include "ephor/arm_cmd_t.hpp"
#include "ephor/arm_goal_t.hpp"
#include "ephor/sched_status_t.hpp"
#include "ephor/shepherd_blobs_t.hpp"
#include "ephor/shepherd_ground_truth_t.hpp"
#include "ephor/shepherd_objects_t.hpp"
#include "procs/shared/monitor/run_monitor.h"

namespace ephor::monitor {

class MonitorFeed {
 public:
  explicit MonitorFeed(RunMonitor& monitor) : monitor_(monitor) {}

  // `now_us`: this host's wall clock when the message arrived.
  void on_truth(const shepherd_ground_truth_t& m);
  void on_blobs(const shepherd_blobs_t& m, int64_t now_us);
  void on_objects(const shepherd_objects_t& m, int64_t now_us);
  void on_arm_goal(const arm_goal_t& m);
  void on_arm_cmd(const arm_cmd_t& m);
  void on_sched_status(const sched_status_t& m);

 private:
  RunMonitor& monitor_;
  std::set<std::pair<std::string, int64_t>> seen_cmds_;    // (sender, seq)
  std::map<std::string, std::pair<bool, int64_t>> hosts_;  // host -> (rt, deadline misses)
};

}  // namespace ephor::monitor
