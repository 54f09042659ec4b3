#include "procs/rambo/sim/sim_messages.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <spdlog/spdlog.h>

#include "common/arm/servo_messages.h"
#include "common/geometry/message_pose.h"
#include "common/rambo/pose_predictor.h"
#include "common/rambo/prediction_message.h"
#include "common/runtime/counts.h"

namespace ephor::rambo {
namespace {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const auto k = static_cast<std::size_t>(
      std::clamp(p * static_cast<double>(v.size() - 1), 0.0, static_cast<double>(v.size() - 1)));
  return v[k];
}

nlohmann::json p50_p99(const std::vector<double>& v) {
  if (v.empty()) return nullptr;
  return {{"p50", percentile(v, 0.5)}, {"p99", percentile(v, 0.99)}, {"n", v.size()}};
}

}  // namespace

SimWorld::SimWorld(RamboCell c, const TumblingMotion& m, const arm::JointLimits& limits)
    : cell(std::move(c)),
      arm(cell.tool_length_mm, limits),
      body(m.pose0, m.velocity_mm_s, m.body_rates_rad_s, cell.principal_moments),
      indicator(cell.diodes, RamboCell::kAcceptanceDeg, RamboCell::kLensRadiusMm,
                RamboCell::kRequiredS),
      servo(limits, cell.start_joints) {}

Eigen::Isometry3d SimWorld::target_at(double t_s) {
  return carrier ? carrier->pose(t_s) : body.pose(t_s);
}

Eigen::Vector3d SimWorld::target_rates_at(double t_s) {
  return carrier ? carrier->body_rates(t_s) : body.body_rates(t_s);
}

Eigen::Isometry3d SimWorld::camera_in_base(const arm::Joints& q) const {
  return arm.forward(q) * cell.camera_in_tool;
}

int64_t SimWorld::utime_of(double t_s) const { return wall0_us + std::llround(t_s * 1e6); }

double SimWorld::t_of(int64_t utime) const {
  // In double: a message's utime can be any int64, and the difference in
  // int64 would overflow (exact for any utime within 2^53 us of 1970).
  return (static_cast<double>(utime) - static_cast<double>(wall0_us)) * 1e-6;
}

void SimWorld::step() {
  if (pending) {
    servo.follow(*pending);
    pending.reset();
  }
  servo.step(kSimStepS);
  clock_s += kSimStepS;
  const Eigen::Isometry3d target = target_at(clock_s);
  const Eigen::Isometry3d tool = arm.forward(servo.state().q);
  indicator.step(clock_s, target, tool.translation(), tool.linear().col(2));
  while (!pending_predictions.empty() && pending_predictions.front().t_eval_s <= clock_s) {
    const auto& p = pending_predictions.front();
    prediction_err_mm[p.horizon].push_back((p.predicted_mm - target.translation()).norm());
    for (std::size_t i = 0; i < p.goals_mm.size(); ++i)
      goal_prediction_err_mm[p.horizon].push_back(
          (p.goals_mm[i] - (target * cell.goal_in_target(static_cast<int>(i))).translation())
              .norm());
    pending_predictions.pop_front();
  }
  if (indicator.tagged_count() != logged_tagged) {
    logged_tagged = indicator.tagged_count();
    spdlog::info("diode {} tagged at {:.2f} s ({} of {})", indicator.lit_diode(), clock_s,
                 logged_tagged, indicator.size());
    if (logged_tagged == indicator.size()) {
      if (all_tagged_s < 0) all_tagged_s = clock_s;
      round_done_s = clock_s;
    }
  }
}

void SimWorld::advance_to(double now_s) {
  if (now_s - clock_s > kSimMaxLagS) {
    spdlog::warn("physics {:.3f} s behind the clock; skipping ahead", now_s - clock_s);
    clock_s = now_s - kSimStepS;
  }
  while (clock_s + kSimStepS <= now_s) step();
}

void SimWorld::on_trajectory(const joint_trajectory_t& m) {
  std::string why;
  auto t = sim::to_trajectory(m, why);
  if (!t) {
    ++refused;
    spdlog::warn("ARM_TRAJECTORY seq {} ignored: {}", m.seq, why);
    return;
  }
  std::lock_guard<std::mutex> lock(mutex);
  pending = std::move(*t);
}

void SimWorld::on_pose(const rambo_pose_t& m) {
  std::lock_guard<std::mutex> lock(mutex);
  ++poses;
  features_source = m.features_source;
  if (!m.found) return;
  const Eigen::Isometry3d est = geometry::pose_of(m.target_r, m.target_t_mm);
  const auto it = truth_by_utime.find(m.utime);
  if (!est.matrix().allFinite() || it == truth_by_utime.end() || !std::isfinite(m.pose_ms)) {
    ++bad_messages;
    return;
  }
  // Finite but huge numbers, or a "rotation" that is not one, give errors
  // that are not finite: a bad message, not a score.
  const double err_mm = (est.translation() - it->second.translation()).norm();
  const double err_deg = rotation_angle_between(est.linear(), it->second.linear()) * 180.0 / M_PI;
  if (!std::isfinite(err_mm) || !std::isfinite(err_deg)) {
    ++bad_messages;
    return;
  }
  ++poses_found;
  pose_err_mm.push_back(err_mm);
  pose_err_deg.push_back(err_deg);
  pose_ms.push_back(m.pose_ms);
  ours_by_utime[m.utime] = {pose_err_mm.back(), pose_err_deg.back(), m.pose_ms};
  while (ours_by_utime.size() > 100) ours_by_utime.erase(ours_by_utime.begin());
}

void SimWorld::on_pose_peer(const rambo_pose_t& m) {
  std::lock_guard<std::mutex> lock(mutex);
  ++peer_poses;
  const auto truth = truth_by_utime.find(m.utime);
  const auto ours = ours_by_utime.find(m.utime);
  if (!m.found || truth == truth_by_utime.end() || ours == ours_by_utime.end()) return;
  const Eigen::Isometry3d est = geometry::pose_of(m.target_r, m.target_t_mm);
  if (!est.matrix().allFinite() || !std::isfinite(m.pose_ms)) {
    ++bad_messages;
    return;
  }
  const double err_mm = (est.translation() - truth->second.translation()).norm();
  const double err_deg =
      rotation_angle_between(est.linear(), truth->second.linear()) * 180.0 / M_PI;
  if (!std::isfinite(err_mm) || !std::isfinite(err_deg)) {
    ++bad_messages;
    return;
  }
  ++peer_found;
  peer_err_mm.push_back(err_mm);
  peer_err_deg.push_back(err_deg);
  peer_ms.push_back(m.pose_ms);
  ours_err_mm.push_back(ours->second[0]);
  ours_err_deg.push_back(ours->second[1]);
  ours_ms.push_back(ours->second[2]);
}

void SimWorld::on_prediction(const rambo_prediction_t& m) {
  if (!m.fitted) return;
  const std::optional<FittedMotion> f = motion_from_message(m, 0.0, nullptr);
  std::lock_guard<std::mutex> lock(mutex);
  if (!f) {
    ++bad_messages;
    return;
  }
  // A fit whose predicted points are not finite (or so large that their
  // distance to the truth is not) is a bad message: it would score NaN.
  const auto scorable = [](const Eigen::Vector3d& p) { return std::isfinite(p.squaredNorm()); };
  const double t_ref = t_of(m.ref_utime);
  std::vector<PendingPrediction> scored;
  for (int h = 0; h < 3; ++h) {
    const Eigen::Isometry3d pose = f->pose(kSimHorizonsS[h]);
    std::vector<Eigen::Vector3d> goals;
    for (int i = 0; i < indicator.size(); ++i)
      goals.push_back((pose * cell.goal_in_target(i)).translation());
    if (!scorable(pose.translation()) || !std::all_of(goals.begin(), goals.end(), scorable)) {
      ++bad_messages;
      return;
    }
    scored.push_back({t_ref + kSimHorizonsS[h], h, pose.translation(), std::move(goals)});
  }
  ++predictions;
  prediction_model = m.model;
  for (PendingPrediction& p : scored) pending_predictions.push_back(std::move(p));
  std::sort(pending_predictions.begin(), pending_predictions.end(),
            [](const PendingPrediction& a, const PendingPrediction& b) {
              return a.t_eval_s < b.t_eval_s;
            });
}

void SimWorld::on_sched_status(const sched_status_t& m) {
  int64_t misses = 0;
  for (const auto& t : m.tasks) misses = add_count(misses, t.deadline_misses);  // saturates
  std::lock_guard<std::mutex> lock(mutex);
  sched_hosts[m.host] = {m.rt != 0, misses};
  for (const auto& t : m.tasks)
    sched_tasks[t.process + "/" + t.task] = {
        {"exec_p50_ms", static_cast<double>(t.exec_p50_us) / 1e3},
        {"exec_p99_ms", static_cast<double>(t.exec_p99_us) / 1e3},
        {"jobs", t.jobs},
        {"deadline_misses", t.deadline_misses},
        {"rt", t.rt_granted != 0}};
}

void SimWorld::on_plan(const rambo_plan_t& m) {
  std::lock_guard<std::mutex> lock(mutex);
  if (!first_order && m.dp_trajectories > 0) first_order = m;
  last_plan = m;
}

std::optional<joint_state_t> SimWorld::physics_tick(double now_s) {
  std::lock_guard<std::mutex> lock(mutex);
  advance_to(now_s);
  if (++ticks % 2 != 0) return std::nullopt;  // ARM_SERVO at 250 Hz
  return sim::to_joint_state(servo.state(), utime_of(clock_s));
}

CameraShot SimWorld::camera_shot(double now_s) {
  CameraShot shot;
  std::lock_guard<std::mutex> lock(mutex);
  advance_to(now_s);
  shot.target = target_at(clock_s);
  if (carrier) {
    const auto c = carrier->chain(clock_s);
    shot.carrier_chain.assign(c.begin(), c.end());
  }
  shot.camera = camera_in_base(servo.state().q);
  shot.truth.utime = utime_of(clock_s);
  const Eigen::Vector3d rates = target_rates_at(clock_s);
  for (int k = 0; k < 3; ++k) shot.truth.body_rates_rad_s[k] = rates[k];
  truth_by_utime[shot.truth.utime] = shot.target;
  while (truth_by_utime.size() > 600) truth_by_utime.erase(truth_by_utime.begin());
  return shot;
}

rambo_indicator_t SimWorld::indicator_tick(double now_s, int rounds, double max_s, bool& finished) {
  rambo_indicator_t m{};
  std::lock_guard<std::mutex> lock(mutex);
  advance_to(now_s);
  const DiodeIndicator& ind = indicator;
  m.utime = utime_of(clock_s);
  m.num_diodes = ind.size();
  m.lit_diode = ind.lit_diode();
  m.lit_s = ind.lit_s();
  m.tagged_count = ind.tagged_count();
  m.acceptance_deg = ind.acceptance_deg();
  m.lens_radius_mm = ind.lens_radius_mm();
  m.required_s = ind.required_s();
  for (int i = 0; i < ind.size(); ++i) {
    m.tagged.push_back(ind.tagged(i));
    m.tagged_utime.push_back(ind.tagged(i) ? static_cast<double>(utime_of(ind.tagged_at_s(i)))
                                           : 0.0);
    m.beam_angle_deg.push_back(ind.readings()[static_cast<std::size_t>(i)].beam_angle_deg);
    m.beam_offset_mm.push_back(
        std::min(ind.readings()[static_cast<std::size_t>(i)].beam_offset_mm, 1e6));
  }
  if (++indicator_ticks % 100 == 0) {  // every 5 s: how close the beam is to each diode
    std::string line;
    for (int i = 0; i < ind.size(); ++i)
      line += fmt::format(
          " {} {:.1f} deg {:.0f} mm{};", cell.diodes[static_cast<std::size_t>(i)].name,
          m.beam_angle_deg[static_cast<std::size_t>(i)],
          m.beam_offset_mm[static_cast<std::size_t>(i)], ind.tagged(i) ? " (tagged)" : "");
    spdlog::info("beam at {:.0f} s:{}", clock_s, line);
  }
  if (round_done_s >= 0 && clock_s > round_done_s + 1.0) {
    ++rounds_done;
    if (rounds == 0 || rounds_done < rounds) {
      spdlog::info("round {} done at {:.1f} s: every diode untagged, the next round starts",
                   rounds_done, clock_s);
      indicator.reset_tags(clock_s);
      round_done_s = -1.0;
      logged_tagged = 0;
    } else {
      finished = true;
    }
  }
  if (clock_s > max_s) finished = true;
  return m;
}

nlohmann::json SimWorld::summary(uint64_t seed, double spin_deg_s) const {
  nlohmann::json j;
  j["system"] = "rambo";
  j["seed"] = seed;
  j["spin_deg_s"] = spin_deg_s;
  j["carrier"] = carrier ? "rm501" : "free";
  j["diodes"] = indicator.size();
  j["tagged"] = indicator.tagged_count();
  j["rounds_completed"] = rounds_done;
  j["time_to_all_s"] = all_tagged_s >= 0 ? nlohmann::json(all_tagged_s) : nlohmann::json(nullptr);
  nlohmann::json tasks = nlohmann::json::array();
  std::vector<std::pair<double, int>> done;
  for (int i = 0; i < indicator.size(); ++i)
    if (indicator.tagged(i)) done.emplace_back(indicator.tagged_at_s(i), i);
  std::sort(done.begin(), done.end());
  // Per task: its place in the order carried out and its time, from the
  // tag before it (the run's start for the first) to its own tag, s.
  double previous_s = 0.0;
  for (const auto& [t, i] : done) {
    tasks.push_back({{"order", tasks.size() + 1},
                     {"diode", i},
                     {"name", cell.diodes[static_cast<std::size_t>(i)].name},
                     {"tagged_s", t},
                     {"time_s", t - previous_s}});
    previous_s = t;
  }
  j["tasks"] = tasks;
  j["diode_acceptance_deg"] = indicator.acceptance_deg();
  j["diode_lens_radius_mm"] = indicator.lens_radius_mm();
  j["diode_required_s"] = indicator.required_s();
  j["poses"] = poses;
  j["poses_found"] = poses_found;
  j["pose_error_mm"] = p50_p99(pose_err_mm);
  j["pose_error_deg"] = p50_p99(pose_err_deg);
  j["pose_ms"] = p50_p99(pose_ms);
  j["pose_features_source"] = features_source;
  j["predictions"] = predictions;
  nlohmann::json pe;
  for (int h = 0; h < 3; ++h)
    pe[fmt::format("{:.1f}s", kSimHorizonsS[h])] = p50_p99(prediction_err_mm[h]);
  j["prediction_error_mm"] = pe;
  nlohmann::json ge;
  for (int h = 0; h < 3; ++h)
    ge[fmt::format("{:.1f}s", kSimHorizonsS[h])] = p50_p99(goal_prediction_err_mm[h]);
  j["goal_prediction_error_mm"] = ge;
  j["prediction_error_of"] =
      "the target frame's origin (prediction_error_mm) and every goal point "
      "(goal_prediction_error_mm, pooled), by the predictor's model (prediction_model)";
  j["prediction_model"] = prediction_model;
  if (first_order) {
    j["reaching_trajectories_computed"] = {{"greedy", first_order->greedy_trajectories},
                                           {"exhaustive", first_order->exhaustive_trajectories},
                                           {"dynamic_programming", first_order->dp_trajectories},
                                           {"tasks", first_order->num_tasks}};
    j["planned_order"] = first_order->order;
  } else {
    j["reaching_trajectories_computed"] = nullptr;
  }
  j["goals_sent"] = last_plan ? last_plan->goals_sent : 0;
  j["frames"] = frames.load();
  j["trajectories_refused"] = refused.load();
  j["bad_messages"] = bad_messages;
  // Summed over the hosts' schedulers; rt only when every host ran its
  // SCHED_FIFO tasks as such (null: no scheduler status heard).
  int64_t misses = 0;
  bool rt = true;
  for (const auto& [host, h] : sched_hosts) {
    rt = rt && h.first;
    misses = add_count(misses, h.second);
  }
  j["deadline_misses"] = sched_hosts.empty() ? nlohmann::json(nullptr) : nlohmann::json(misses);
  j["rt"] = sched_hosts.empty() ? nlohmann::json(nullptr) : nlohmann::json(rt);
  j["sched_hosts"] = sched_hosts.size();
  j["sched_tasks"] = sched_tasks;
  // The peer (OpenCV solvePnPRansac over all point-vertex pairs) on the
  // frames ephor-rambo-pose gave it (--peer-every), and ours on the same
  // frames (those where both found a pose).
  j["peer"] = {{"method", "cv::solvePnPRansac AP3P over every image point x model vertex"},
               {"poses", peer_poses},
               {"found_with_ours", peer_found},
               {"pose_error_mm", p50_p99(peer_err_mm)},
               {"pose_error_deg", p50_p99(peer_err_deg)},
               {"pose_ms", p50_p99(peer_ms)},
               {"ours_pose_error_mm", p50_p99(ours_err_mm)},
               {"ours_pose_error_deg", p50_p99(ours_err_deg)},
               {"ours_pose_ms", p50_p99(ours_ms)}};
  return j;
}

}  // namespace ephor::rambo
