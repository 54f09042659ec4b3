#pragma once
// DisplayState: the newest view of the system as the display heard it, as
// plain structs (main.cc converts LCM messages), assembled into the JSON the
// page draws from (GET /api/state). Image frame: px, u right, v down; times
// in the JSON are ms unless named otherwise.
//
// Not thread-safe: main.cc holds one lock around every call.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "procs/shepherd/display/command_validator.h"
#include "procs/shepherd/display/overlay_geometry.h"

namespace ephor::display {

struct Blob {
  double u = 0.0;  // centroid, px
  double v = 0.0;
  int area = 0;  // px
};

struct BlobsView {
  int64_t frame_index = 0;
  int mode = 0;  // shepherd_vision_cmd_t.MODE_*
  int scan = 0;  // shepherd_vision_cmd_t.SCAN_*
  int threshold = 0;
  double processing_us = 0.0;
  std::vector<Blob> blobs;
};

struct TrackedObject {
  int id = 0;
  int state = 0;            // shepherd_object_t.STATE_* (0 visible, 1 obscured, 2 dead)
  double u = 0.0, v = 0.0;  // px
  double vu_px_s = 0.0, vv_px_s = 0.0;
  double since_seen_s = 0.0;
  int area = 0;
};

struct PlannerView {
  std::string planner;
  std::string phase;
  int target_object = -1;
  double intercept_u = 0.0, intercept_v = 0.0;  // px
  double intercept_time_s = 0.0;
  double planning_us = 0.0;
  int64_t goal_id = 0;
};

struct ArmView {
  double u = 0.0, v = 0.0;  // tool tip in the image, px
  double theta_rad = 0.0;   // manipulator orientation in the image
  double z_mm = 0.0;        // tool tip height in F
  bool moving = false;
  double speed_mm_s = 0.0;
};

struct TruthSheep {
  int id = 0;
  double u = 0.0, v = 0.0;  // px
  bool visible = false;
  bool on_field = false;
};

struct TruthView {
  std::vector<TruthSheep> sheep;
  int escapes = 0;
  int saves = 0;
  double sim_time_s = 0.0;
};

struct DisplayOptions {
  double path_horizon_s = 3.0;  // predicted paths: velocity x this
  int path_steps = 6;
  double tool_radius_mm = 40.0;  // footprint of the manipulator tip on the table
};

class DisplayState {
 public:
  DisplayState(OverlayGeometry geometry, DisplayOptions options);

  // now_us: wall clock when the message arrived (for ages in the JSON).
  void on_frame(int64_t frame_index, int width_px, int height_px, int64_t now_us);
  void on_blobs(BlobsView blobs, int64_t now_us);
  void on_objects(std::vector<TrackedObject> objects, int64_t now_us);
  void on_planner(PlannerView planner, int64_t now_us);
  void on_arm(ArmView arm, int64_t now_us);
  void on_truth(TruthView truth, int64_t now_us);
  // One arm command: frame-to-command latency = sent_utime - source_frame_utime
  // (both wall clock, us). A (sender, seq) seen before (a resend) is not counted.
  void on_arm_command(const std::string& sender, int64_t seq, int64_t source_frame_utime,
                      int64_t sent_utime);

  // The page's whole state. `controls` = the current desired state.
  nlohmann::json to_json(const Controls& controls, int64_t now_us) const;

  // Circles the page will draw (one per blob of the newest BLOBS).
  size_t circle_count() const { return blobs_ ? blobs_->blobs.size() : 0; }
  const std::optional<BlobsView>& blobs() const { return blobs_; }

 private:
  OverlayGeometry geometry_;
  DisplayOptions options_;
  int64_t frame_index_ = -1;
  int width_px_ = 0, height_px_ = 0;
  int64_t frame_us_ = 0;
  std::optional<BlobsView> blobs_;
  int64_t blobs_us_ = 0;
  std::optional<std::vector<TrackedObject>> objects_;
  int64_t objects_us_ = 0;
  std::optional<PlannerView> planner_;
  int64_t planner_us_ = 0;
  std::optional<ArmView> arm_;
  int64_t arm_us_ = 0;
  std::optional<TruthView> truth_;
  int64_t truth_us_ = 0;
  std::map<std::string, int64_t> last_cmd_seq_;  // sender -> newest arm_cmd_t.seq counted
  std::vector<double> latencies_ms_;             // ring of the newest frame-to-command latencies
  size_t latency_next_ = 0;
};

}  // namespace ephor::display
