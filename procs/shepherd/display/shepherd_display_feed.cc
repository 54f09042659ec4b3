#include "procs/shepherd/display/shepherd_display_feed.h"

#include <utility>
#include <vector>

namespace ephor::display {

ShepherdDisplayFeed::ShepherdDisplayFeed(const OverlayGeometry& geometry,
                                         const DisplayOptions& options, int sim_seed)
    : state_(geometry, options) {
  controls_.sim.seed = sim_seed;
}

void ShepherdDisplayFeed::on_frame(const camera_frame_t& m, int64_t now_us) {
  frame_width_ = m.width;
  frame_height_ = m.height;
  state_.on_frame(m.frame_index, m.width, m.height, now_us);
}

void ShepherdDisplayFeed::on_blobs(const shepherd_blobs_t& m, int64_t now_us) {
  BlobsView b;
  b.frame_index = m.frame_index;
  b.mode = m.mode;
  b.scan = m.scan;
  b.threshold = m.threshold;
  b.processing_us = static_cast<double>(m.processing_us);
  for (const auto& x : m.blobs) b.blobs.push_back({x.u, x.v, x.area});
  state_.on_blobs(std::move(b), now_us);
  if (!vision_known_) {  // nobody commanded vision yet: take over its current mode
    controls_.vision.mode = m.mode;
    controls_.vision.scan = m.scan;
    vision_known_ = true;
  }
}

void ShepherdDisplayFeed::on_vision_cmd(const shepherd_vision_cmd_t& m) {
  controls_.vision = {m.paused != 0, m.mode, m.scan, m.threshold};
  vision_known_ = true;
}

void ShepherdDisplayFeed::on_objects(const shepherd_objects_t& m, int64_t now_us) {
  std::vector<TrackedObject> objs;
  objs.reserve(m.objects.size());
  for (const auto& o : m.objects)
    objs.push_back({o.id, o.state, o.u, o.v, o.vu_px_s, o.vv_px_s, o.since_seen_s, o.area});
  state_.on_objects(std::move(objs), now_us);
}

void ShepherdDisplayFeed::on_planner_status(const shepherd_planner_status_t& m, int64_t now_us) {
  state_.on_planner({m.planner, m.phase, m.target_object, m.intercept_u, m.intercept_v,
                     m.intercept_time_s, m.planning_us, m.goal_id},
                    now_us);
  if (!planner_known_ && !m.planner.empty()) {
    controls_.planner = m.planner;
    planner_known_ = true;
  }
}

void ShepherdDisplayFeed::on_planner_cmd(const shepherd_planner_cmd_t& m) {
  controls_.planner = m.planner;
  planner_known_ = true;
}

void ShepherdDisplayFeed::on_arm_state(const arm_state_t& m, int64_t now_us) {
  state_.on_arm({m.u, m.v, m.theta_rad, m.z_mm, m.moving != 0, m.speed_mm_s}, now_us);
}

void ShepherdDisplayFeed::on_truth(const shepherd_ground_truth_t& m, int64_t now_us) {
  TruthView t;
  t.escapes = m.escapes;
  t.saves = m.saves;
  t.sim_time_s = m.sim_time_s;
  for (const auto& s : m.sheep)
    t.sheep.push_back({s.id, s.u, s.v, s.visible != 0, s.on_field != 0});
  if (!sim_known_) {  // nobody commanded the simulator yet: its herd as it is
    controls_.sim.sheep = m.num_sheep;
    sim_known_ = true;
  }
  state_.on_truth(std::move(t), now_us);
}

void ShepherdDisplayFeed::on_sim_cmd(const shepherd_sim_cmd_t& m) {
  controls_.sim = {m.sheep, m.seed};
  sim_known_ = true;
}

void ShepherdDisplayFeed::on_arm_cmd(const arm_cmd_t& m) {
  state_.on_arm_command(m.header.sender, m.seq, m.source_frame_utime, m.header.utime);
}

}  // namespace ephor::display
