#include "procs/sphere/display/sphere_display_state.h"

#include <algorithm>
#include <cmath>

#include "common/display/json_format.h"

namespace ephor::sphere_display {
namespace {

using display::age_ms;

using display::r1;
using display::rounded;

constexpr double kDegPerRad = 180.0 / 3.14159265358979323846;

double norm(const Vec3& p) { return std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]); }
double lateral(const Vec3& p) { return std::hypot(p[0], p[1]); }
bool finite(const Vec3& p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

// Where the sphere's centre appears in the raster, and its angular radius.
struct Angles {
  double azimuth_deg, elevation_deg, radius_deg;
};
Angles angles_of(const Vec3& p, double radius_m) {
  const double r = norm(p);
  Angles a;
  a.azimuth_deg = std::atan2(p[0], p[2]) * kDegPerRad;
  a.elevation_deg = std::atan2(p[1], std::hypot(p[0], p[2])) * kDegPerRad;
  a.radius_deg = r > radius_m ? std::asin(radius_m / r) * kDegPerRad : 90.0;
  return a;
}

nlohmann::json vec(const Vec3& v, int digits) {
  return nlohmann::json::array(
      {rounded(v[0], digits), rounded(v[1], digits), rounded(v[2], digits)});
}

// Where the centre is: angles (deg), range and offset from the boresight (m).
void put_place(nlohmann::json& j, const Vec3& p, double radius_m) {
  const auto a = angles_of(p, radius_m);
  j["position_m"] = vec(p, 4);
  j["azimuth_deg"] = rounded(a.azimuth_deg, 4);
  j["elevation_deg"] = rounded(a.elevation_deg, 4);
  j["radius_deg"] = rounded(a.radius_deg, 4);
  j["range_m"] = rounded(norm(p), 4);
  j["lateral_m"] = rounded(lateral(p), 4);
}

double percentile(const std::vector<double>& sorted, double q) {
  const auto i = static_cast<size_t>(std::lround(q * static_cast<double>(sorted.size() - 1)));
  return sorted[std::min(i, sorted.size() - 1)];
}

const char* guidance_phase(int phase) {
  switch (phase) {
    case 0:
      return "acquire";
    case 1:
      return "closing";
    case 2:
      return "final";
    default:
      return "unknown";
  }
}

const char* truth_phase(int phase) {
  switch (phase) {
    case 0:
      return "approach";
    case 1:
      return "captured";
    case 2:
      return "missed";
    default:
      return "unknown";
  }
}

}  // namespace

SphereDisplayState::SphereDisplayState(SphereDisplayOptions options) : options_(options) {}

void SphereDisplayState::on_scan_line(const ScanLineView& line, int64_t now_us) {
  ++lines_heard_;
  if (collecting_.window >= 0 && line.window > collecting_.window) complete_raster(now_us);
  if (collecting_.window >= 0 && line.window < collecting_.window) {
    collecting_ = Raster{};  // the scan clock went back (a restarted ranger): start over
  }
  collecting_.window = line.window;
  collecting_.half_extent_deg = line.half_extent_deg;
  ++collecting_.lines;
  const size_t n =
      std::min({line.azimuth_rad.size(), line.elevation_rad.size(), line.range_m.size()});
  for (size_t i = 0; i < n; ++i) {
    const double az = line.azimuth_rad[i], el = line.elevation_rad[i], r = line.range_m[i];
    if (!std::isfinite(r) || !std::isfinite(az) || !std::isfinite(el) || r <= 0.0) {
      ++collecting_.no_return;
      continue;
    }
    collecting_.points.push_back({az * kDegPerRad, el * kDegPerRad, r, 0});
  }
  if (line.last_in_window) complete_raster(now_us);
}

void SphereDisplayState::complete_raster(int64_t now_us) {
  if (collecting_.window < 0) return;
  Raster r = std::move(collecting_);
  collecting_ = Raster{};
  std::vector<double> foreground;
  for (const auto& p : r.points)
    if (p.range_m < options_.background_m) foreground.push_back(p.range_m);
  std::sort(foreground.begin(), foreground.end());
  if (!foreground.empty()) {
    r.range_lo_m = percentile(foreground, 0.02);
    r.range_hi_m = std::max(percentile(foreground, 0.98), r.range_lo_m + 0.01);
  }
  const double span = r.range_hi_m - r.range_lo_m;
  for (auto& p : r.points) {
    if (p.range_m >= options_.background_m) {
      p.bin = -1;
      ++r.background;
      continue;
    }
    const double x = std::floor((p.range_m - r.range_lo_m) / span * kRangeBins);
    p.bin = static_cast<int>(std::clamp(x, 0.0, static_cast<double>(kRangeBins - 1)));
  }
  raster_ = std::move(r);
  raster_us_ = now_us;
}

void SphereDisplayState::clear_history() {
  estimate_history_.clear();
  guidance_history_.clear();
  truth_history_.clear();
}

void SphereDisplayState::add_sample(Series& series, double t_s, const Vec3& p) {
  if (!std::isfinite(t_s) || !finite(p)) return;
  if (!series.empty() && t_s < series.back().t_s - 1.0) series.clear();  // the clock went back
  // (1e-9: samples exactly one spacing apart are kept despite rounding.)
  if (!series.empty() && t_s - series.back().t_s < options_.history_spacing_s - 1e-9) return;
  series.push_back({t_s, norm(p), lateral(p)});
  while (series.size() > options_.history_samples) series.pop_front();
}

void SphereDisplayState::on_estimate(const EstimateView& estimate, int64_t now_us) {
  estimate_ = estimate;
  estimate_us_ = now_us;
  if (!estimate.ok) {
    ++estimates_failed_;
    return;
  }
  add_sample(estimate_history_, estimate.t_s, estimate.position_m);
}

void SphereDisplayState::on_guidance(const GuidanceView& guidance, int64_t now_us) {
  guidance_ = guidance;
  guidance_us_ = now_us;
  if (guidance.estimates_used > 0) add_sample(guidance_history_, guidance.t_s, guidance.position_m);
}

void SphereDisplayState::on_truth(const TruthView& truth, int64_t now_us) {
  if (approach_ >= 0 && truth.approach != approach_) clear_history();  // a fresh sphere
  approach_ = truth.approach;
  if (truth.phase != 0 && truth.approach != last_judged_approach_) {
    last_judged_approach_ = truth.approach;
    (truth.phase == 1 ? captured_ : missed_)++;
  }
  if (truth.phase != 0) last_verdict_ = truth;
  truth_ = truth;
  truth_us_ = now_us;
  if (truth.phase == 0) add_sample(truth_history_, truth.t_s, truth.position_m);
}

nlohmann::json SphereDisplayState::to_json(int64_t now_us) const {
  using nlohmann::json;
  json j;
  j["capture_distance_m"] = options_.capture_distance_m;
  j["sphere_radius_m"] = options_.sphere_radius_m;
  j["range_bins"] = kRangeBins;
  j["lines_heard"] = lines_heard_;

  if (raster_) {
    j["scan"] = {{"window", raster_->window},
                 {"half_extent_deg", rounded(raster_->half_extent_deg, 4)},
                 {"lines", raster_->lines},
                 {"points", raster_->points.size()},
                 {"no_return", raster_->no_return},
                 {"background", raster_->background},
                 {"range_lo_m", rounded(raster_->range_lo_m, 3)},
                 {"range_hi_m", rounded(raster_->range_hi_m, 3)},
                 {"age_ms", r1(age_ms(raster_us_, now_us))}};
  } else {
    j["scan"] = nullptr;
  }

  if (estimate_) {
    const auto& e = *estimate_;
    json je = {{"window", e.window},
               {"ok", e.ok},
               {"reason", e.reason},
               {"t_s", rounded(e.t_s, 3)},
               {"points", e.points},
               {"lines", e.lines},
               {"lines_missing", e.lines_missing},
               {"cpu_us", r1(e.cpu_us)},
               {"algorithm", e.algorithm},
               {"variant", e.variant},
               {"failed", estimates_failed_},
               {"age_ms", r1(age_ms(estimate_us_, now_us))}};
    if (e.ok && finite(e.position_m)) {
      put_place(je, e.position_m, options_.sphere_radius_m);
      je["velocity_m_s"] = vec(e.velocity_m_s, 4);
    }
    j["estimate"] = je;
  } else {
    j["estimate"] = nullptr;
  }

  if (guidance_ && finite(guidance_->position_m)) {
    const auto& g = *guidance_;
    json jg = {{"t_s", rounded(g.t_s, 3)},
               {"tracking", g.estimates_used > 0},
               {"sigma_m", vec(g.position_sigma_m, 4)},
               {"velocity_m_s", vec(g.velocity_m_s, 4)},
               {"velocity_sigma_m_s", vec(g.velocity_sigma_m_s, 4)},
               {"chaser_velocity_m_s", vec(g.chaser_velocity_m_s, 4)},
               {"range_to_capture_m", rounded(g.range_to_capture_m, 3)},
               {"phase", guidance_phase(g.phase)},
               {"estimates_used", g.estimates_used},
               {"estimates_downweighted", g.estimates_downweighted},
               {"estimates_rejected", g.estimates_rejected},
               {"no_estimates", g.no_estimates},
               {"age_ms", r1(age_ms(guidance_us_, now_us))}};
    put_place(jg, g.position_m, options_.sphere_radius_m);
    // 1 sigma across the line of sight as angles: the ellipse drawn on the raster.
    const double r = norm(g.position_m), rxz = std::hypot(g.position_m[0], g.position_m[2]);
    jg["sigma_deg"] = {rxz > 0 ? rounded(g.position_sigma_m[0] / rxz * kDegPerRad, 5) : 0.0,
                       r > 0 ? rounded(g.position_sigma_m[1] / r * kDegPerRad, 5) : 0.0};
    j["guidance"] = jg;
  } else {
    j["guidance"] = nullptr;
  }

  if (truth_ && finite(truth_->position_m)) {
    const auto& t = *truth_;
    json jt = {{"t_s", rounded(t.t_s, 3)},      {"approach", t.approach},
               {"phase", truth_phase(t.phase)}, {"speed_m_s", rounded(norm(t.velocity_m_s), 4)},
               {"verdict", t.verdict},          {"age_ms", r1(age_ms(truth_us_, now_us))}};
    put_place(jt, t.position_m, options_.sphere_radius_m);
    j["truth"] = jt;
  } else {
    j["truth"] = nullptr;
  }
  if (last_verdict_) {
    const auto& v = *last_verdict_;
    j["last_verdict"] = {{"approach", v.approach},
                         {"phase", truth_phase(v.phase)},
                         {"verdict", v.verdict},
                         {"capture_t_s", rounded(v.capture_t_s, 2)},
                         {"capture_speed_m_s", rounded(v.capture_speed_m_s, 4)},
                         {"capture_offset_m", rounded(v.capture_offset_m, 4)}};
  } else {
    j["last_verdict"] = nullptr;
  }
  j["approaches"] = {{"captured", captured_}, {"missed", missed_}};

  auto series = [](const Series& s) {
    json a = json::array();
    for (const auto& x : s)
      a.push_back({rounded(x.t_s, 2), rounded(x.range_m, 4), rounded(x.lateral_m, 4)});
    return a;
  };
  j["history"] = {{"estimate", series(estimate_history_)},
                  {"guidance", series(guidance_history_)},
                  {"truth", series(truth_history_)}};
  return j;
}

nlohmann::json SphereDisplayState::scan_json() const {
  using nlohmann::json;
  if (!raster_) return nullptr;
  json points = json::array();
  for (const auto& p : raster_->points) {
    points.push_back(
        {rounded(p.azimuth_deg, 3), rounded(p.elevation_deg, 3), rounded(p.range_m, 3), p.bin});
  }
  return {{"window", raster_->window},
          {"half_extent_deg", rounded(raster_->half_extent_deg, 4)},
          {"range_lo_m", rounded(raster_->range_lo_m, 3)},
          {"range_hi_m", rounded(raster_->range_hi_m, 3)},
          {"bins", kRangeBins},
          {"points", points}};
}

}  // namespace ephor::sphere_display
