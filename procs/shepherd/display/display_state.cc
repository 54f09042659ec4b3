#include "procs/shepherd/display/display_state.h"

#include <algorithm>
#include <cmath>

#include "common/display/json_format.h"

namespace ephor::display {
namespace {

constexpr size_t kLatencyWindow = 200;  // commands kept for the latency percentiles

const char* mode_name(int mode) { return mode == 1 ? "trackify" : "blobify"; }
const char* scan_name(int scan) { return scan == 1 ? "axis" : "full"; }
const char* state_name(int state) {
  switch (state) {
    case 0:
      return "visible";
    case 1:
      return "obscured";
    default:
      return "dead";
  }
}

nlohmann::json point(const ImagePoint& p) { return nlohmann::json::array({r1(p.u), r1(p.v)}); }

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<size_t>(std::lround(q * static_cast<double>(v.size() - 1)));
  return v[std::min(i, v.size() - 1)];
}

}  // namespace

DisplayState::DisplayState(OverlayGeometry geometry, DisplayOptions options)
    : geometry_(std::move(geometry)), options_(options) {}

void DisplayState::on_frame(int64_t frame_index, int width_px, int height_px, int64_t now_us) {
  frame_index_ = frame_index;
  width_px_ = width_px;
  height_px_ = height_px;
  frame_us_ = now_us;
}

void DisplayState::on_blobs(BlobsView blobs, int64_t now_us) {
  blobs_ = std::move(blobs);
  blobs_us_ = now_us;
}

void DisplayState::on_objects(std::vector<TrackedObject> objects, int64_t now_us) {
  objects_ = std::move(objects);
  objects_us_ = now_us;
}

void DisplayState::on_planner(PlannerView planner, int64_t now_us) {
  planner_ = std::move(planner);
  planner_us_ = now_us;
}

void DisplayState::on_arm(ArmView arm, int64_t now_us) {
  arm_ = arm;
  arm_us_ = now_us;
}

void DisplayState::on_truth(TruthView truth, int64_t now_us) {
  truth_ = std::move(truth);
  truth_us_ = now_us;
}

void DisplayState::on_arm_command(const std::string& sender, int64_t seq,
                                  int64_t source_frame_utime, int64_t sent_utime) {
  const auto it = last_cmd_seq_.find(sender);
  if (it != last_cmd_seq_.end() && seq <= it->second) return;  // a resend, or old
  last_cmd_seq_[sender] = seq;
  if (source_frame_utime <= 0 || sent_utime < source_frame_utime) return;  // no frame behind it
  const double ms = static_cast<double>(sent_utime - source_frame_utime) / 1e3;
  if (latencies_ms_.size() < kLatencyWindow) {
    latencies_ms_.push_back(ms);
  } else {
    latencies_ms_[latency_next_] = ms;
  }
  latency_next_ = (latency_next_ + 1) % kLatencyWindow;
}

nlohmann::json DisplayState::to_json(const Controls& controls, int64_t now_us) const {
  using nlohmann::json;
  json j;
  j["utime"] = now_us;
  j["frame"] = {{"index", frame_index_},
                {"width", width_px_},
                {"height", height_px_},
                {"age_ms", r1(age_ms(frame_us_, now_us))}};

  json boundary = json::array();
  for (const auto& p : geometry_.field_boundary()) boundary.push_back(point(p));
  j["boundary"] = boundary;

  if (blobs_) {
    json list = json::array();
    for (const auto& b : blobs_->blobs) {
      list.push_back({r1(b.u), r1(b.v), r1(OverlayGeometry::blob_radius_px(b.area)), b.area});
    }
    j["blobs"] = {{"frame_index", blobs_->frame_index},
                  {"mode", mode_name(blobs_->mode)},
                  {"scan", scan_name(blobs_->scan)},
                  {"threshold", blobs_->threshold},
                  {"processing_us", r1(blobs_->processing_us)},
                  {"age_ms", r1(age_ms(blobs_us_, now_us))},
                  {"circles", list}};
  } else {
    j["blobs"] = nullptr;
  }

  json objects = json::array();
  if (objects_) {
    for (const auto& o : *objects_) {
      if (o.state == 2) continue;  // dead: gone from the field
      json path = json::array();
      for (const auto& p : OverlayGeometry::predicted_path(
               o.u, o.v, o.vu_px_s, o.vv_px_s, options_.path_horizon_s, options_.path_steps)) {
        path.push_back(point(p));
      }
      objects.push_back({{"id", o.id},
                         {"state", state_name(o.state)},
                         {"u", r1(o.u)},
                         {"v", r1(o.v)},
                         {"vu", r1(o.vu_px_s)},
                         {"vv", r1(o.vv_px_s)},
                         {"since_seen_s", r1(o.since_seen_s)},
                         {"path", path}});
    }
  }
  j["objects"] = objects;
  j["objects_age_ms"] = r1(age_ms(objects_us_, now_us));
  j["path_horizon_s"] = options_.path_horizon_s;

  if (planner_) {
    j["planner"] = {{"planner", planner_->planner},
                    {"phase", planner_->phase},
                    {"target", planner_->target_object},
                    {"u", r1(planner_->intercept_u)},
                    {"v", r1(planner_->intercept_v)},
                    {"time_s", r1(planner_->intercept_time_s)},
                    {"planning_us", r1(planner_->planning_us)},
                    {"goal_id", planner_->goal_id},
                    {"age_ms", r1(age_ms(planner_us_, now_us))}};
  } else {
    j["planner"] = nullptr;
  }

  if (arm_) {
    j["arm"] = {{"u", r1(arm_->u)},
                {"v", r1(arm_->v)},
                {"theta_rad", rounded(arm_->theta_rad, 3)},
                {"z_mm", r1(arm_->z_mm)},
                {"moving", arm_->moving},
                {"speed_mm_s", r1(arm_->speed_mm_s)},
                {"footprint_px", r1(options_.tool_radius_mm * geometry_.px_per_mm())},
                {"age_ms", r1(age_ms(arm_us_, now_us))}};
  } else {
    j["arm"] = nullptr;
  }

  if (truth_) {
    json sheep = json::array();
    int on_field = 0, visible = 0;
    for (const auto& s : truth_->sheep) {
      if (s.on_field) ++on_field;
      if (s.on_field && s.visible) ++visible;
      sheep.push_back({{"id", s.id},
                       {"u", r1(s.u)},
                       {"v", r1(s.v)},
                       {"visible", s.visible},
                       {"on_field", s.on_field}});
    }
    j["truth"] = {{"sheep", sheep},
                  {"on_field", on_field},
                  {"visible", visible},
                  {"saves", truth_->saves},
                  {"escapes", truth_->escapes},
                  {"elapsed_s", r1(truth_->sim_time_s)},
                  {"age_ms", r1(age_ms(truth_us_, now_us))}};
  } else {
    j["truth"] = nullptr;
  }

  j["latency"] = {{"commands", latencies_ms_.size()},
                  {"p50_ms", r1(percentile(latencies_ms_, 0.5))},
                  {"p99_ms", r1(percentile(latencies_ms_, 0.99))},
                  {"max_ms", r1(percentile(latencies_ms_, 1.0))}};

  j["controls"] = {{"paused", controls.vision.paused},
                   {"mode", mode_name(controls.vision.mode)},
                   {"scan", scan_name(controls.vision.scan)},
                   {"threshold", controls.vision.threshold},
                   {"planner", controls.planner},
                   {"sheep", controls.sim.sheep},
                   {"box",
                    {{"visible", controls.box.visible},
                     {"u", r1(controls.box.u)},
                     {"v", r1(controls.box.v)},
                     {"half", r1(controls.box.half_size_px)}}}};
  return j;
}

}  // namespace ephor::display
