#include "procs/rambo/pose/pose_task.h"

#include <utility>

#include "common/time/clock.h"

namespace ephor::rambo {

std::optional<FittedMotion> prior_motion_of(const rambo_prediction_t& m) {
  if (!m.fitted) return std::nullopt;
  FittedMotion fm;
  fm.t_ref_s = static_cast<double>(m.ref_utime) * 1e-6;
  fm.position_mm = Eigen::Vector3d(m.position_mm[0], m.position_mm[1], m.position_mm[2]);
  fm.velocity_mm_s = Eigen::Vector3d(m.velocity_mm_s[0], m.velocity_mm_s[1], m.velocity_mm_s[2]);
  fm.orientation = Eigen::Quaterniond(m.orientation_wxyz[0], m.orientation_wxyz[1],
                                      m.orientation_wxyz[2], m.orientation_wxyz[3]);
  fm.body_rates_rad_s =
      Eigen::Vector3d(m.body_rates_rad_s[0], m.body_rates_rad_s[1], m.body_rates_rad_s[2]);
  fm.principal_moments =
      Eigen::Vector3d(m.principal_moments[0], m.principal_moments[1], m.principal_moments[2]);
  if (!fm.finite()) return std::nullopt;
  fm.orientation.normalize();
  return fm;
}

std::optional<arm::Joints> joints_of(const arm_state_t& m) {
  arm::Joints q;
  for (int j = 0; j < 6; ++j) q[j] = m.q[j];
  if (!q.allFinite()) return std::nullopt;
  return q;
}

namespace {
// b - a in us as a double: utimes from the bus can be anything, and their
// int64_t difference can overflow (undefined); exact below 2^53 us.
double minus_us(int64_t b, int64_t a) { return static_cast<double>(b) - static_cast<double>(a); }
}  // namespace

std::optional<arm::Joints> PoseFrameQueue::joints_at(int64_t utime) const {
  if (joints_.empty() || utime < joints_.front().first) return std::nullopt;
  if (utime >= joints_.back().first)
    return minus_us(utime, joints_.back().first) < 50'000 ? std::optional(joints_.back().second)
                                                          : std::nullopt;
  for (std::size_t k = 1; k < joints_.size(); ++k) {
    if (joints_[k].first < utime) continue;
    const double a =
        minus_us(utime, joints_[k - 1].first) / minus_us(joints_[k].first, joints_[k - 1].first);
    return arm::Joints((1.0 - a) * joints_[k - 1].second + a * joints_[k].second);
  }
  return std::nullopt;
}

// The frame taken up with the camera's joints and the predictor's motion as
// they are when it becomes ready, in the order messages came: what its pose
// then depends on does not depend on how long the pose task took to get to it.
void PoseFrameQueue::make_ready(rambo_features_t f) {
  ReadyFrame r;
  r.q = joints_at(f.utime);
  r.motion = motion_;
  r.features = std::move(f);
  ready_.push_back(std::move(r));
}

bool PoseFrameQueue::on_arm_state(int64_t utime, const arm::Joints& q) {
  if (!joints_.empty() && utime <= joints_.back().first) return false;
  joints_.emplace_back(utime, q);
  while (joints_.size() > kMaxStates) joints_.pop_front();
  if (!waiting_ || utime < waiting_->utime) return false;
  make_ready(std::move(*waiting_));
  waiting_.reset();
  return true;
}

bool PoseFrameQueue::on_features(const rambo_features_t& m) {
  // A newer frame: the one still waiting goes as it is (its camera pose from
  // the last state, or none).
  if (waiting_) make_ready(std::move(*waiting_));
  waiting_.reset();
  if (!joints_.empty() && joints_.back().first >= m.utime)
    make_ready(m);
  else
    waiting_ = m;
  while (ready_.size() > static_cast<std::size_t>(max_behind_)) {
    ready_.pop_front();
    ++dropped_;
  }
  return !ready_.empty();
}

std::optional<ReadyFrame> PoseFrameQueue::take() {
  if (ready_.empty()) return std::nullopt;
  std::optional<ReadyFrame> r = std::move(ready_.front());
  ready_.pop_front();
  return r;
}

bool triples_of(const rambo_features_t& f, std::vector<ImageTriple>* triples) {
  triples->clear();
  bool finite = static_cast<int>(f.triples_px.size()) == f.num_triples;
  for (const auto& t : f.triples_px) {
    ImageTriple it;
    it.reference_px = {t[0], t[1]};
    it.a_px = {t[2], t[3]};
    it.b_px = {t[4], t[5]};
    finite = finite && it.reference_px.allFinite() && it.a_px.allFinite() && it.b_px.allFinite();
    triples->push_back(it);
  }
  return finite;
}

FramePoser::FramePoser(const RamboCell& cell, const TrianglePoseEstimator& estimator,
                       double prior_max_age_s)
    : cell_(cell),
      estimator_(estimator),
      prior_max_age_s_(prior_max_age_s),
      arm_(cell.tool_length_mm) {}

rambo_pose_t FramePoser::pose(
    const ReadyFrame& frame, bool* malformed,
    const std::function<void(const std::vector<ImageTriple>&, const Eigen::Isometry3d&)>&
        before_estimate) {
  const rambo_features_t* f = &frame.features;
  rambo_pose_t out{};
  out.utime = f->utime;
  out.frame_index = f->frame_index;
  out.features_source = f->source;
  out.camera_r[0] = out.camera_r[4] = out.camera_r[8] = 1.0;  // unknown until the joints are
  std::vector<ImageTriple> triples;
  const bool finite = triples_of(*f, &triples);
  const std::optional<arm::Joints>& q = frame.q;
  const std::optional<FittedMotion>& motion_then = frame.motion;
  std::optional<Eigen::Isometry3d> prior_in_base;
  const double t_frame = static_cast<double>(f->utime) * 1e-6;
  if (motion_then && prior_max_age_s_ > 0 &&
      t_frame - motion_then->t_ref_s <= 5.0 * prior_max_age_s_ && t_frame >= motion_then->t_ref_s)
    prior_in_base = motion_then->pose(t_frame);
  else if (last_ && prior_max_age_s_ > 0 &&
           minus_us(f->utime, last_->first) * 1e-6 <= prior_max_age_s_)
    prior_in_base = last_->second;
  *malformed = !finite;
  if (!finite) {
    out.reason = "features message malformed (sizes or non-finite pixels)";
  } else if (!q) {
    out.reason = "no arm state at the frame's capture time (camera pose unknown)";
  } else if (triples.empty()) {
    out.reason = "no image triples in the frame";
  } else {
    const Eigen::Isometry3d camera = arm_.forward(*q) * cell_.camera_in_tool;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) out.camera_r[3 * i + j] = camera.linear()(i, j);
      out.camera_t_mm[i] = camera.translation()[i];
    }
    if (before_estimate) before_estimate(triples, camera);
    const Eigen::Isometry3d prior =
        prior_in_base ? camera.inverse() * *prior_in_base : Eigen::Isometry3d::Identity();
    const int64_t cpu0 = thread_cpu_ns();
    const TrianglePoseResult r = estimator_.estimate(triples, prior_in_base ? &prior : nullptr);
    out.pose_ms = static_cast<double>(thread_cpu_ns() - cpu0) * 1e-6;
    out.pruned = prior_in_base.has_value();
    out.matches_tried = r.matches_tried;
    out.cluster_size = r.cluster_size;
    out.correspondences = r.correspondences;
    out.rms_reprojection_px = r.rms_reprojection_px;
    out.found = r.found;
    out.reason = r.reason;
    for (const MatchedTriangle& m : matched_triangles(cell_.model, triples, r)) {
      const ImageTriple& t = triples[static_cast<std::size_t>(m.triple)];
      out.matched_triangles_px.push_back(
          {t.reference_px.x(), t.reference_px.y(), t.a_px.x(), t.a_px.y(), t.b_px.x(), t.b_px.y()});
      out.matched_triangle_vertices.push_back({m.vertices.reference, m.vertices.a, m.vertices.b});
    }
    out.num_matched_triangles = static_cast<int32_t>(out.matched_triangles_px.size());
    if (r.found) {
      const Eigen::Isometry3d in_base = camera * r.target_in_camera;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) out.target_r[3 * i + j] = in_base.linear()(i, j);
        out.target_t_mm[i] = in_base.translation()[i];
      }
      last_ = std::make_pair(f->utime, in_base);
    }
  }
  return out;
}

}  // namespace ephor::rambo
