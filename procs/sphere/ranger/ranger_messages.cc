#include "procs/sphere/ranger/ranger_messages.h"

#include <cmath>
#include <limits>

#include <spdlog/spdlog.h>

namespace ephor::sphere {

sphere_scan_line_t scan_line_message(const RangerLine& l, double window_s, int64_t utime) {
  sphere_scan_line_t m{};
  m.utime = utime;
  m.line = l.line.id;
  m.window = l.window;
  m.window_s = window_s;
  m.last_in_window = l.last_in_window;
  m.half_extent_deg = static_cast<float>(l.half_extent_deg);
  m.num_pulses = static_cast<int32_t>(l.line.pulses.size());
  for (const Pulse& p : l.line.pulses) {
    m.t_s.push_back(p.t_s);
    m.azimuth_rad.push_back(p.azimuth_rad);
    m.elevation_rad.push_back(p.elevation_rad);
    m.range_m.push_back(p.range_m);
  }
  return m;
}

void fill_truth(sphere_truth_t& m, const RangerTruth& t) {
  m.t_s = t.t_s;
  m.approach = t.approach;
  for (int i = 0; i < 3; ++i) {
    m.position_m[i] = t.position_m[i];
    m.velocity_m_s[i] = t.velocity_m_s[i];
    m.chaser_velocity_m_s[i] = t.chaser_velocity_m_s[i];
    m.target_velocity_m_s[i] = t.target_velocity_m_s[i];
  }
  m.half_extent_deg = static_cast<float>(t.half_extent_deg);
}

RangerProcess::RangerProcess(RangerWorld& world, int64_t wall0_us)
    : world_(world), wall0_us_(wall0_us) {}

int64_t RangerProcess::utime_of(double t_s) const { return wall0_us_ + std::llround(t_s * 1e6); }

bool RangerProcess::on_guidance(const sphere_guidance_t& m) {
  const Eigen::Vector3d v(m.chaser_velocity_m_s[0], m.chaser_velocity_m_s[1],
                          m.chaser_velocity_m_s[2]);
  bool ok;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ok = world_.command(m.apply_t_s, v);
  }
  if (!ok) {
    const int64_t n = ++commands_refused_;
    if (n <= 10 || n % 100 == 0) {
      spdlog::warn("SPHERE_GUIDANCE from {} ignored: non-finite time or velocity ({} so far)",
                   m.header.sender, n);
    }
    return false;
  }
  ++commands_;
  return true;
}

RangerProcess::Scan RangerProcess::scan(double t_s) {
  std::vector<RangerLine> lines;
  Scan out;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    lines = world_.advance_to(t_s);
    while (verdicts_published_ < world_.verdicts().size()) {
      const CaptureVerdict& v = world_.verdicts()[verdicts_published_];
      sphere_truth_t m{};
      // The state at the verdict's moment (the window it fell in is the
      // current one unless the next sphere has already come).
      RangerTruth t = world_.truth_at(v.t_s);
      t.position_m = v.position_m;
      t.velocity_m_s = v.velocity_m_s;
      t.approach = static_cast<int>(verdicts_published_);
      fill_truth(m, t);
      m.utime = utime_of(v.t_s);
      m.phase = v.captured ? sphere_truth_t::PHASE_CAPTURED : sphere_truth_t::PHASE_MISSED;
      m.capture_t_s = v.t_s;
      m.capture_speed_m_s = v.speed_m_s;
      m.capture_offset_m = v.offset_m;
      m.verdict = v.text;
      spdlog::info("approach {}: {}", verdicts_published_, v.text);
      out.verdicts.push_back(m);
      ++verdicts_published_;
    }
    if (world_.finished()) finished_ = true;
  }
  const double window_s = world_.config().motion.window_s;
  for (const RangerLine& l : lines) {
    out.lines.push_back(scan_line_message(l, window_s, utime_of(l.ready_t_s)));
    ++lines_published_;
  }
  return out;
}

std::optional<sphere_truth_t> RangerProcess::truth(double t_s) {
  sphere_truth_t m{};
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (world_.finished()) return std::nullopt;
    const double window_s = world_.config().motion.window_s;
    if (static_cast<double>(world_.windows_started()) * window_s <= t_s)
      return std::nullopt;  // scan lags
    fill_truth(m, world_.truth_at(t_s));
    m.utime = utime_of(t_s);
  }
  m.phase = sphere_truth_t::PHASE_APPROACH;
  m.capture_t_s = std::numeric_limits<double>::quiet_NaN();
  return m;
}

}  // namespace ephor::sphere
