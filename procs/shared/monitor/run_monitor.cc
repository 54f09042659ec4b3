#include "procs/shared/monitor/run_monitor.h"

#include <spdlog/fmt/fmt.h>

#include <cmath>
#include <cstdio>
#include <limits>

namespace ephor::monitor {
namespace {

constexpr int64_t kRateWindowUs = 5'000'000;

void push_time(std::deque<int64_t>& q, int64_t now_us) {
  q.push_back(now_us);
  while (!q.empty() && q.front() < now_us - kRateWindowUs) q.pop_front();
}

double rate_hz(const std::deque<int64_t>& q) {
  // Two messages in the same microsecond (a burst after a stall) give no span to divide by.
  if (q.size() < 2 || q.back() <= q.front()) return 0.0;
  return static_cast<double>(q.size() - 1) / (static_cast<double>(q.back() - q.front()) * 1e-6);
}

}  // namespace

nlohmann::json Summary::to_json() const {
  nlohmann::json j;
  j["scenario"] = scenario;
  j["duration_s"] = duration_s;
  j["sheep"] = sheep;
  j["escapes"] = escapes;
  j["saves"] = saves;
  j["vision_rate_hz"] = vision_rate_hz;
  j["objects_rate_hz"] = objects_rate_hz;
  j["latency_ms"] = {
      {"p50", latency_p50_ms}, {"p99", latency_p99_ms}, {"samples", latency_samples}};
  j["id_switches"] = id_switches;
  j["position_error_px_rms"] = position_error_px_rms;
  j["deadline_misses"] = deadline_misses;
  j["rt"] = rt;
  j["scheduler_seen"] = have_sched_status;
  j["arm_commands"] = arm_commands;
  for (const auto& st : stages)
    j["pipeline_latency_ms"][st.name] = {
        {"p50", st.p50_ms}, {"p99", st.p99_ms}, {"samples", st.samples}};
  return j;
}

RunMonitor::RunMonitor(std::string scenario, double match_radius_mm)
    : scenario_(std::move(scenario)), match_radius_mm_(match_radius_mm) {}

void RunMonitor::on_truth(const Truth& truth) {
  if (start_us_ == 0) start_us_ = truth.utime;
  // An escape: which sheep left, and where it was last seen on the field (a
  // log reader's first question about a run).
  if (!truths_.empty() && truth.escapes > last_truth_.escapes) {
    for (const auto& before : last_truth_.sheep) {
      if (!before.on_field) continue;
      bool still_on = false;
      for (const auto& now : truth.sheep) still_on |= now.id == before.id && now.on_field;
      if (!still_on)
        events_.push_back(
            fmt::format("escape: sheep {} left the field at ({:.0f}, {:.0f}) mm ({:.1f} s)",
                        before.id, before.x_mm, before.y_mm, truth.sim_time_s));
    }
  }
  last_truth_ = truth;
  truths_.push_back(truth);
  while (truths_.size() > 120) truths_.pop_front();
}

namespace {
void add_latency(RollingStats& stats, int64_t from_us, int64_t to_us) {
  if (from_us > 0 && to_us >= from_us) stats.add(static_cast<double>(to_us - from_us) / 1000.0);
}
}  // namespace

void RunMonitor::on_blobs(int64_t frame_utime, int64_t published_us, int64_t now_us) {
  push_time(blob_times_, now_us);
  add_latency(blobs_ms_, frame_utime, published_us);
}

void RunMonitor::on_arm_goal(int64_t source_frame_utime, int64_t published_us) {
  add_latency(goal_ms_, source_frame_utime, published_us);
}

void RunMonitor::on_objects(int64_t frame_utime, int64_t published_us,
                            const std::vector<TrackedObject>& objects, int64_t now_us) {
  push_time(object_times_, now_us);
  add_latency(objects_ms_, frame_utime, published_us);
  const Truth* truth = nullptr;
  for (const auto& t : truths_)
    if (t.utime == frame_utime) truth = &t;
  if (truth == nullptr)
    return;  // no ground truth for this frame (real camera, or not yet received)
  for (const auto& s : truth->sheep) {
    if (!s.on_field) {
      // An escaped sheep re-enters under its old truth id, but for the
      // tracker it is a new sheep: its next object is not a switch.
      matched_.erase(s.id);
      continue;
    }
    if (!s.visible) continue;
    const TrackedObject* best = nullptr;
    double best_d = match_radius_mm_;
    for (const auto& o : objects) {
      if (o.dead) continue;
      const double d = std::hypot(o.x_mm - s.x_mm, o.y_mm - s.y_mm);
      if (d <= best_d) {
        best_d = d;
        best = &o;
      }
    }
    if (best == nullptr) continue;
    auto it = matched_.find(s.id);
    if (it != matched_.end() && it->second != best->id) {
      ++id_switches_;
      const int32_t old_id = it->second;
      std::string was = "gone from OBJECTS";
      for (const auto& o : objects)
        if (o.id == old_id)
          was = o.dead ? "dead"
                       : fmt::format("at ({:.0f}, {:.0f}) mm, {}", o.x_mm, o.y_mm,
                                     o.visible ? "visible" : "obscured");
      events_.push_back(fmt::format(
          "id switch: sheep {} at ({:.0f}, {:.0f}) mm ({:.1f} s) was object {} ({}), now object {}",
          s.id, s.x_mm, s.y_mm, truth->sim_time_s, old_id, was, best->id));
    }
    matched_[s.id] = best->id;
    if (best->visible) {
      err_sq_sum_ += (best->u - s.u) * (best->u - s.u) + (best->v - s.v) * (best->v - s.v);
      ++err_n_;
    }
  }
}

std::vector<std::string> RunMonitor::take_events() {
  std::vector<std::string> out;
  out.swap(events_);
  return out;
}

void RunMonitor::on_arm_command(int64_t source_frame_utime, int64_t sent_us) {
  ++arm_commands_;
  add_latency(latency_ms_, source_frame_utime, sent_us);
}

void RunMonitor::on_sched_status(bool rt, int64_t deadline_misses_total) {
  have_sched_ = true;
  rt_ = rt;
  deadline_misses_ = deadline_misses_total;
}

Summary RunMonitor::summary(int64_t now_us) const {
  Summary s;
  s.scenario = scenario_;
  s.duration_s = last_truth_.sim_time_s;
  for (const auto& sh : last_truth_.sheep) s.sheep += sh.on_field ? 1 : 0;
  s.escapes = last_truth_.escapes;
  s.saves = last_truth_.saves;
  auto fresh = [now_us](const std::deque<int64_t>& q) {
    return !q.empty() && now_us - q.back() < 2'000'000;
  };
  s.vision_rate_hz = fresh(blob_times_) ? rate_hz(blob_times_) : 0.0;
  s.objects_rate_hz = fresh(object_times_) ? rate_hz(object_times_) : 0.0;
  s.latency_p50_ms = latency_ms_.percentile(50);
  s.latency_p99_ms = latency_ms_.percentile(99);
  s.latency_samples = static_cast<int64_t>(latency_ms_.size());
  s.id_switches = id_switches_;
  s.position_error_px_rms = err_n_ > 0 ? std::sqrt(err_sq_sum_ / static_cast<double>(err_n_)) : 0.0;
  s.deadline_misses = deadline_misses_;
  s.rt = rt_;
  s.have_sched_status = have_sched_;
  s.arm_commands = arm_commands_;
  auto stage = [](const char* name, const RollingStats& r) {
    return Summary::Stage{name, r.percentile(50), r.percentile(99), static_cast<int64_t>(r.size())};
  };
  s.stages = {stage("blobs", blobs_ms_), stage("objects", objects_ms_), stage("arm_goal", goal_ms_),
              stage("arm_cmd", latency_ms_)};
  return s;
}

std::string RunMonitor::status_line(int64_t now_us) const {
  const Summary s = summary(now_us);
  char buf[320];
  std::snprintf(
      buf, sizeof buf,
      "t=%.0fs  sheep on field %d  saves %d  escapes %d  vision %.1f Hz  objects %.1f Hz  "
      "arm cmds %lld  latency p50 %.2f ms p99 %.2f ms  id switches %lld  rt %s",
      s.duration_s, s.sheep, s.saves, s.escapes, s.vision_rate_hz, s.objects_rate_hz,
      static_cast<long long>(s.arm_commands), s.latency_p50_ms, s.latency_p99_ms,
      static_cast<long long>(s.id_switches), !s.have_sched_status ? "?" : (s.rt ? "yes" : "no"));
  return buf;
}

}  // namespace ephor::monitor
