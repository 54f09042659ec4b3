#pragma once
// CatchMonitorFeed: ephor-catch-monitor's LCM handlers without LCM. Each
// message is converted as the process takes it and handed to CatchSummary:
// out of main.cc so that the fuzz target catch_monitor_feed_fuzz.cc runs
// what the process runs.

#include <optional>
#include <string>

#include "common/catch/summary/catch_summary.h"
#include "ephor/catch_board_pose_t.hpp"
#include "ephor/catch_truth_t.hpp"
#include "ephor/catch_world_t.hpp"
#include "ephor/sched_status_t.hpp"

namespace ephor::catching {

class CatchMonitorFeed {
 public:
  explicit CatchMonitorFeed(CatchSummary& summary) : summary_(summary) {}

  // Returns a line for the log when the truth judges a new ball ("ball 3:
  // caught ..." or "ball 3: missed: ...").
  std::optional<std::string> on_truth(const catch_truth_t& m);
  void on_world(const catch_world_t& m);
  // A pose marked not valid is ignored.
  void on_board_pose(const catch_board_pose_t& m);
  void on_sched_status(const sched_status_t& m);

 private:
  CatchSummary& summary_;
  int last_logged_ = -1;  // the last ball whose outcome was logged
};

}  // namespace ephor::catching
