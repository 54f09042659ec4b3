#include "procs/rambo/display/rambo_display_feed.h"

#include <cmath>
#include <utility>

#include <Eigen/Geometry>

#include "common/geometry/message_pose.h"

namespace ephor::rambo_display {
namespace {

bool finite(const Eigen::Isometry3d& p) { return p.matrix().allFinite(); }

}  // namespace

void RamboDisplayFeed::on_features(const rambo_features_t& m) {
  FeaturesView f;
  f.utime = m.utime;
  f.frame_index = m.frame_index;
  f.source = m.source;
  f.triples = m.num_triples;
  if (static_cast<int>(m.corners_px.size()) != m.num_corners ||
      static_cast<int>(m.edges.size()) != m.num_edges)
    return;  // malformed: the pose process names it
  for (const auto& c : m.corners_px)
    if (std::isfinite(c[0]) && std::isfinite(c[1])) f.corners_px.push_back({c[0], c[1]});
  for (const auto& e : m.edges)
    if (e[0] >= 0 && e[1] >= 0 && e[0] < static_cast<int>(f.corners_px.size()) &&
        e[1] < static_cast<int>(f.corners_px.size()))
      f.edges.push_back({e[0], e[1]});
  state_.on_features(std::move(f));
}

void RamboDisplayFeed::on_pose(const rambo_pose_t& m) {
  PoseView p;
  p.utime = m.utime;
  p.frame_index = m.frame_index;
  p.found = m.found;
  p.reason = m.reason;
  p.target_in_base = geometry::pose_of(m.target_r, m.target_t_mm);
  p.camera_in_base = geometry::pose_of(m.camera_r, m.camera_t_mm);
  p.pose_ms = m.pose_ms;
  p.correspondences = m.correspondences;
  p.pruned = m.pruned;
  p.features_source = m.features_source;
  if (p.found && (!finite(p.target_in_base) || !finite(p.camera_in_base))) return;
  if (static_cast<int>(m.matched_triangles_px.size()) == m.num_matched_triangles)
    for (const auto& t : m.matched_triangles_px)
      p.matched_triangles_px.push_back({t[0], t[1], t[2], t[3], t[4], t[5]});
  state_.on_pose(std::move(p));
}

void RamboDisplayFeed::on_truth(const rambo_truth_t& m) {
  TruthView t;
  t.utime = m.utime;
  t.frame_index = m.frame_index;
  t.target_in_base = geometry::pose_of(m.target_r, m.target_t_mm);
  t.camera_in_base = geometry::pose_of(m.camera_r, m.camera_t_mm);
  for (const auto& p : m.carrier_mm) {
    const Eigen::Vector3d v(p.at(0), p.at(1), p.at(2));
    if (!v.allFinite()) return;
    t.carrier_mm.push_back(v);
  }
  if (finite(t.target_in_base) && finite(t.camera_in_base)) state_.on_truth(t);
}

void RamboDisplayFeed::on_plan(const rambo_plan_t& m) {
  PlanView p;
  p.order = m.order;
  p.current_task = m.current_task;
  p.status = m.status;
  p.greedy_trajectories = m.greedy_trajectories;
  p.exhaustive_trajectories = m.exhaustive_trajectories;
  p.dp_trajectories = m.dp_trajectories;
  p.order_total_s = m.order_total_s;
  p.goals_sent = m.goals_sent;
  state_.on_plan(std::move(p));
}

void RamboDisplayFeed::on_indicator(const rambo_indicator_t& m) {
  IndicatorView i;
  i.utime = m.utime;
  i.lit_diode = m.lit_diode;
  i.lit_s = m.lit_s;
  i.required_s = m.required_s;
  i.acceptance_deg = m.acceptance_deg;
  i.tagged.assign(m.tagged.begin(), m.tagged.end());
  i.tagged_utime = m.tagged_utime;
  i.beam_angle_deg = m.beam_angle_deg;
  i.beam_offset_mm = m.beam_offset_mm;
  state_.on_indicator(std::move(i));
}

void RamboDisplayFeed::on_arm_state(const arm_state_t& m) {
  arm::Joints q;
  for (int j = 0; j < 6; ++j) q[j] = m.q[j];
  state_.on_arm_joints(q);
}

}  // namespace ephor::rambo_display
