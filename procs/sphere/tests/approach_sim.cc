#include "procs/sphere/tests/approach_sim.h"

#include <cmath>
#include <cstdio>

namespace ephor::sphere {

ApproachSimConfig approach_sim_config(uint64_t seed, double start_m, double max_s) {
  ApproachSimConfig c;
  c.world.seed = seed;
  c.world.motion.start_position_m = Eigen::Vector3d(0.0, 0.0, start_m);
  c.world.motion.target_velocity_m_s = RelativeMotionConfig::table1_drift(start_m);
  c.world.max_s = max_s;
  c.world.approaches = 1;
  return c;
}

ApproachResult fly_approach(const ApproachSimConfig& config) {
  RangerWorld world(config.world);
  const SphereLocator locator(config.locator);
  SphereGuidance guidance(config.guidance);
  const double w = config.world.motion.window_s;
  ApproachResult r;
  double est_sq[3] = {0, 0, 0}, filt_sq[3] = {0, 0, 0};
  for (int64_t k = 0; !world.finished(); ++k) {
    const double t_end = static_cast<double>(k + 1) * w;
    Window win;
    win.t_begin_s = static_cast<double>(k) * w;
    win.t_end_s = t_end;
    // Lines of window k are all out by its end (the last pulse is 0.1 ms before it).
    std::vector<RangerLine> lines = world.advance_to(t_end - 1e-9);
    // The truth of window k, read before the world moves on to k + 1.
    const SphereTrajectory truth_k = world.motion().trajectory();
    for (RangerLine& l : lines) win.lines.push_back(std::move(l.line));
    if (world.finished()) break;
    world.advance_to(t_end);  // starts window k + 1
    ++r.windows;
    double cpu_us = 0.0;
    const Estimate e = locator.locate(win, &cpu_us);
    r.estimate_cpu_us_max = std::max(r.estimate_cpu_us_max, cpu_us);
    EstimateInput in;
    in.window = k;
    in.window_end_s = t_end;
    in.ok = e.ok;
    in.t_s = e.t_s;
    in.position_m = e.position_m;
    in.velocity_m_s = e.velocity_m_s;
    const auto out = guidance.on_estimate(in);
    if (e.ok) {
      ++r.estimates;
      const Eigen::Vector3d truth = truth_k.centre_at(e.t_s);
      const Eigen::Vector3d de = e.position_m - truth;
      const Eigen::Vector3d df = out ? Eigen::Vector3d(out->state.position_m - truth) : de;
      for (int i = 0; i < 3; ++i) {
        est_sq[i] += de[i] * de[i];
        filt_sq[i] += df[i] * df[i];
      }
      if (config.verbose) {
        std::printf(
            "w %3lld t %6.2f truth (%7.3f %7.3f %7.3f) v (%6.3f %6.3f %6.3f) est err (%6.1f %6.1f "
            "%6.1f) mm filt err (%6.1f %6.1f %6.1f) mm vfilt err (%6.1f %6.1f %6.1f) mm/s upd %d\n",
            static_cast<long long>(k), e.t_s, truth.x(), truth.y(), truth.z(),
            truth_k.velocity_m_s.x(), truth_k.velocity_m_s.y(), truth_k.velocity_m_s.z(),
            de.x() * 1e3, de.y() * 1e3, de.z() * 1e3, df.x() * 1e3, df.y() * 1e3, df.z() * 1e3,
            out ? (out->state.velocity_m_s.x() - truth_k.velocity_m_s.x()) * 1e3 : 0.0,
            out ? (out->state.velocity_m_s.y() - truth_k.velocity_m_s.y()) * 1e3 : 0.0,
            out ? (out->state.velocity_m_s.z() - truth_k.velocity_m_s.z()) * 1e3 : 0.0,
            out ? static_cast<int>(out->update) : -1);
      }
    } else {
      ++r.no_estimates;
      if (config.verbose) {
        std::printf("w %3lld no estimate: %s\n", static_cast<long long>(k), e.reason.c_str());
      }
    }
    if (out) {
      if (out->update == SphereTracker::Update::kReinitialised) ++r.reinitialised;
      world.command(out->apply_t_s, out->command.chaser_velocity_m_s);
    }
  }
  r.rejected = guidance.estimates_rejected();
  r.downweighted = guidance.estimates_downweighted();
  if (!world.verdicts().empty()) {
    r.judged = true;
    r.verdict = world.verdicts().front();
  }
  for (int i = 0; i < 3; ++i) {
    r.estimate_rms_m[i] = r.estimates > 0 ? std::sqrt(est_sq[i] / r.estimates) : 0.0;
    r.filter_rms_m[i] = r.estimates > 0 ? std::sqrt(filt_sq[i] / r.estimates) : 0.0;
  }
  return r;
}

}  // namespace ephor::sphere
