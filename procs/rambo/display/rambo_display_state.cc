#include "procs/rambo/display/rambo_display_state.h"

#include <cmath>

#include "common/display/json_format.h"

namespace ephor::rambo_display {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

using display::rounded;

// A time in us carried as a double (rambo_indicator_t.tagged_utime) as an
// integer for the JSON; null when it is not a time (NaN, beyond int64_t).
nlohmann::json utime_json(double utime) {
  if (!(std::fabs(utime) < 9.2e18)) return nullptr;
  return static_cast<int64_t>(utime);
}

// Rounded for the page: mm to 0.1, rotations to 1e-5, px to 0.1.
nlohmann::json pose_json(const Eigen::Isometry3d& p) {
  nlohmann::json r = nlohmann::json::array(), t = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r.push_back(rounded(p.linear()(i, j), 5));
    t.push_back(rounded(p.translation()[i], 1));
  }
  return {{"r", r}, {"t_mm", t}};
}

nlohmann::json vec_json(const Eigen::Vector3d& v, int digits) {
  return {rounded(v.x(), digits), rounded(v.y(), digits), rounded(v.z(), digits)};
}

}  // namespace

RamboDisplayState::RamboDisplayState(rambo::RamboCell cell)
    : cell_(std::move(cell)), arm_(cell_.tool_length_mm) {}

std::string RamboDisplayState::diode_name(int i) const {
  if (i < 0 || i >= static_cast<int>(cell_.diodes.size())) return "diode " + std::to_string(i);
  return cell_.diodes[static_cast<std::size_t>(i)].name;
}

void RamboDisplayState::on_pose(PoseView p) {
  ++poses_;
  if (p.found) {
    ++poses_found_;
    const auto it = truth_by_utime_.find(p.utime);
    if (it != truth_by_utime_.end()) {
      error_ = std::make_pair(
          (p.target_in_base.translation() - it->second.translation()).norm(),
          Eigen::AngleAxisd(p.target_in_base.linear().transpose() * it->second.linear()).angle() *
              kRadToDeg);
    } else {
      error_.reset();
    }
    found_ = p;
  }
  pose_ = std::move(p);
}

void RamboDisplayState::on_truth(const TruthView& t) {
  truth_ = t;
  truth_by_utime_[t.utime] = t.target_in_base;
  while (truth_by_utime_.size() > 50) truth_by_utime_.erase(truth_by_utime_.begin());
}

void RamboDisplayState::on_arm_joints(const arm::Joints& q) {
  if (q.allFinite()) tool_ = arm_.forward(q);
}

std::vector<std::array<double, 4>> RamboDisplayState::outline_px(
    const Eigen::Isometry3d& target_in_base, const Eigen::Isometry3d& camera_in_base) const {
  std::vector<std::array<double, 4>> out;
  const Eigen::Isometry3d in_camera = camera_in_base.inverse() * target_in_base;
  const std::vector<bool> visible = cell_.model.visible_edges(in_camera.inverse().translation());
  const auto& v = cell_.model.vertices();
  for (std::size_t e = 0; e < cell_.model.edges().size(); ++e) {
    if (!visible[e]) continue;
    const Eigen::Vector3d a = in_camera * v[static_cast<std::size_t>(cell_.model.edges()[e][0])];
    const Eigen::Vector3d b = in_camera * v[static_cast<std::size_t>(cell_.model.edges()[e][1])];
    if (a.z() <= 1.0 || b.z() <= 1.0) continue;  // behind the camera
    const Eigen::Vector2d pa = cell_.camera.project(a), pb = cell_.camera.project(b);
    out.push_back({rounded(pa.x(), 1), rounded(pa.y(), 1), rounded(pb.x(), 1), rounded(pb.y(), 1)});
  }
  return out;
}

nlohmann::json RamboDisplayState::state() const {
  nlohmann::json j;
  // The camera image's overlays.
  nlohmann::json image = {{"width", cell_.camera.width_px}, {"height", cell_.camera.height_px}};
  if (features_) {
    nlohmann::json corners = nlohmann::json::array(), edges = nlohmann::json::array();
    for (const auto& c : features_->corners_px)
      corners.push_back({rounded(c[0], 1), rounded(c[1], 1)});
    for (const auto& e : features_->edges) edges.push_back({e[0], e[1]});
    image["features"] = {{"frame_index", features_->frame_index},
                         {"source", features_->source},
                         {"corners", corners},
                         {"edges", edges},
                         {"triples", features_->triples}};
  } else {
    image["features"] = nullptr;
  }
  if (pose_) {
    nlohmann::json tri = nlohmann::json::array();
    for (const auto& t : pose_->matched_triangles_px) {
      nlohmann::json one = nlohmann::json::array();
      for (double x : t) one.push_back(rounded(x, 1));
      tri.push_back(one);
    }
    image["matched_triangles"] = tri;
    image["pose_frame_index"] = pose_->frame_index;
  } else {
    image["matched_triangles"] = nlohmann::json::array();
    image["pose_frame_index"] = nullptr;
  }
  // The estimated outline only over the frame the pose is of: a pose from
  // an older frame would be drawn where the target no longer is.
  nlohmann::json outline = nlohmann::json::array();
  if (pose_ && pose_->found)
    for (const auto& s : outline_px(pose_->target_in_base, pose_->camera_in_base))
      outline.push_back(s);
  image["estimated_outline"] = outline;
  j["image"] = image;

  // The poses.
  nlohmann::json pose;
  if (pose_) {
    pose["newest"] = {{"frame_index", pose_->frame_index},
                      {"found", pose_->found},
                      {"reason", pose_->reason},
                      {"pose_ms", rounded(pose_->pose_ms, 3)},
                      {"correspondences", pose_->correspondences},
                      {"matched_triangles", pose_->matched_triangles_px.size()},
                      {"pruned", pose_->pruned},
                      {"features_source", pose_->features_source}};
  } else {
    pose["newest"] = nullptr;
  }
  if (found_) {
    nlohmann::json est = pose_json(found_->target_in_base);
    est["frame_index"] = found_->frame_index;
    est["error_mm"] = error_ ? nlohmann::json(rounded(error_->first, 2)) : nullptr;
    est["error_deg"] = error_ ? nlohmann::json(rounded(error_->second, 2)) : nullptr;
    pose["estimated"] = est;
  } else {
    pose["estimated"] = nullptr;
  }
  if (truth_) {
    nlohmann::json tr = pose_json(truth_->target_in_base);
    tr["frame_index"] = truth_->frame_index;
    nlohmann::json chain = nlohmann::json::array();
    for (const Eigen::Vector3d& p : truth_->carrier_mm) chain.push_back(vec_json(p, 1));
    tr["carrier_mm"] = chain;
    pose["true"] = tr;
    pose["camera"] = pose_json(truth_->camera_in_base);
  } else {
    pose["true"] = nullptr;
    pose["camera"] = nullptr;
  }
  pose["poses"] = poses_;
  pose["poses_found"] = poses_found_;
  j["pose"] = pose;

  // The laser: tool tip and beam (tool z), base frame.
  if (tool_) {
    j["laser"] = {{"tip_mm", vec_json(tool_->translation(), 1)},
                  {"beam", vec_json(tool_->linear().col(2), 4)}};
  } else {
    j["laser"] = nullptr;
  }

  // The plan.
  if (plan_) {
    nlohmann::json order = nlohmann::json::array();
    for (int d : plan_->order) order.push_back({{"diode", d}, {"name", diode_name(d)}});
    j["plan"] = {{"order", order},
                 {"current", plan_->current_task >= 0
                                 ? nlohmann::json{{"diode", plan_->current_task},
                                                  {"name", diode_name(plan_->current_task)}}
                                 : nlohmann::json(nullptr)},
                 {"status", plan_->status},
                 {"trajectories",
                  {{"greedy", plan_->greedy_trajectories},
                   {"exhaustive", plan_->exhaustive_trajectories},
                   {"dynamic_programming", plan_->dp_trajectories}}},
                 {"order_total_s", rounded(plan_->order_total_s, 2)},
                 {"goals_sent", plan_->goals_sent}};
  } else {
    j["plan"] = nullptr;
  }

  // The diodes: the cell's, with the indicator's state when heard.
  nlohmann::json diodes = nlohmann::json::array();
  int tagged = 0;
  for (int i = 0; i < static_cast<int>(cell_.diodes.size()); ++i) {
    const auto k = static_cast<std::size_t>(i);
    nlohmann::json d = {{"index", i}, {"name", diode_name(i)}};
    const bool heard = indicator_ && k < indicator_->tagged.size();
    d["tagged"] = heard && indicator_->tagged[k];
    d["lit"] = indicator_ && indicator_->lit_diode == i;
    d["tagged_utime"] = heard && k < indicator_->tagged_utime.size() && indicator_->tagged[k]
                            ? utime_json(indicator_->tagged_utime[k])
                            : nlohmann::json(nullptr);
    d["beam_angle_deg"] = heard && k < indicator_->beam_angle_deg.size()
                              ? nlohmann::json(rounded(indicator_->beam_angle_deg[k], 1))
                              : nlohmann::json(nullptr);
    d["beam_offset_mm"] = heard && k < indicator_->beam_offset_mm.size()
                              ? nlohmann::json(rounded(indicator_->beam_offset_mm[k], 1))
                              : nlohmann::json(nullptr);
    tagged += d["tagged"].get<bool>() ? 1 : 0;
    diodes.push_back(d);
  }
  j["diodes"] = diodes;
  j["indicator"] = {{"heard", indicator_.has_value()},
                    {"tagged", tagged},
                    {"of", cell_.diodes.size()},
                    {"lit_diode", indicator_ ? indicator_->lit_diode : -1},
                    {"lit_s", indicator_ ? rounded(indicator_->lit_s, 2) : 0.0},
                    {"required_s", indicator_ ? rounded(indicator_->required_s, 2) : 0.0},
                    {"acceptance_deg", indicator_ ? rounded(indicator_->acceptance_deg, 2) : 0.0}};
  return j;
}

nlohmann::json RamboDisplayState::model() const {
  nlohmann::json vertices = nlohmann::json::array(), faces = nlohmann::json::array(),
                 diodes = nlohmann::json::array();
  for (const auto& v : cell_.model.vertices()) vertices.push_back(vec_json(v, 2));
  for (const auto& f : cell_.model.faces()) faces.push_back(f);
  for (std::size_t i = 0; i < cell_.diodes.size(); ++i) {
    const rambo::Diode& d = cell_.diodes[i];
    diodes.push_back(
        {{"name", d.name},
         {"lens_mm", vec_json(d.lens_mm, 2)},
         {"axis", vec_json(d.axis, 4)},
         {"goal_mm", vec_json(cell_.goal_in_target(static_cast<int>(i)).translation(), 1)}});
  }
  return {{"vertices", vertices},
          {"faces", faces},
          {"diodes", diodes},
          {"camera",
           {{"fx_px", cell_.camera.fx_px},
            {"fy_px", cell_.camera.fy_px},
            {"cx_px", cell_.camera.cx_px},
            {"cy_px", cell_.camera.cy_px},
            {"width_px", cell_.camera.width_px},
            {"height_px", cell_.camera.height_px}}}};
}

}  // namespace ephor::rambo_display
