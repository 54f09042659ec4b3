#pragma once
// SphereDisplayState: the sphere system's page state (paper 002; issue 15):
// the newest complete half-second raster of the range finder as points
// (azimuth x elevation, coloured by range), the locator's estimate, the
// guidance's filtered sphere with its uncertainty, the ground truth, and the
// approach over time (range and lateral offset) with the capture verdict.
// Plain structs in (main.cc converts the LCM messages), JSON out (GET
// /api/state and /api/scan).
//
// Frames and units: the sensor frame of paper 002's equations 35-37, X right,
// Y up, Z along the boresight, metres; azimuth A and elevation E with
// X = R sin A cos E, Y = R sin E, Z = R cos A cos E. The JSON gives angles
// in degrees, lengths in metres, times on the ranger's scan clock (s).
//
// Range colours: the raster's foreground ranges (finite, below the
// background distance) are split into kRangeBins equal bins between their
// 2nd and 98th percentiles (noise outliers would otherwise stretch the
// scale); nearer than the low end is bin 0, farther than the high end the
// last bin, a background return bin -1, no return no point at all.
//
// Not thread-safe: DisplayServer holds one lock around every call.

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ephor::sphere_display {

using Vec3 = std::array<double, 3>;

// One scan line (sphere_scan_line_t), its pulses in firing order.
struct ScanLineView {
  int64_t line = 0;
  int64_t window = 0;  // k of the half-second window [kW, (k+1)W)
  bool last_in_window = false;
  double half_extent_deg = 0.0;
  std::vector<double> azimuth_rad, elevation_rad, range_m;  // range NaN = no return
};

// The locator's estimate (sphere_estimate_t).
struct EstimateView {
  int64_t window = 0;
  bool ok = false;
  std::string reason;  // why there is none (ok false)
  double t_s = 0.0;
  Vec3 position_m{};
  Vec3 velocity_m_s{};
  int points = 0, lines = 0, lines_missing = 0;
  double cpu_us = 0.0;
  std::string algorithm, variant;
};

// The guidance's filtered sphere and command (sphere_guidance_t).
struct GuidanceView {
  double t_s = 0.0;
  Vec3 position_m{}, velocity_m_s{};
  Vec3 position_sigma_m{}, velocity_sigma_m_s{};  // 1 sigma per axis
  Vec3 chaser_velocity_m_s{};
  double range_to_capture_m = 0.0;
  int phase = 0;  // sphere_guidance_t.PHASE_*: 0 acquire, 1 closing, 2 final
  int estimates_used = 0, estimates_downweighted = 0, estimates_rejected = 0, no_estimates = 0;
};

// The ranger's ground truth (sphere_truth_t).
struct TruthView {
  double t_s = 0.0;
  int approach = 0;
  int phase = 0;  // sphere_truth_t.PHASE_*: 0 approach, 1 captured, 2 missed
  Vec3 position_m{}, velocity_m_s{};
  double capture_t_s = 0.0, capture_speed_m_s = 0.0, capture_offset_m = 0.0;
  std::string verdict;
};

struct SphereDisplayOptions {
  double sphere_radius_m = 0.08;    // 16 cm sphere (paper 002, section 1)
  double capture_distance_m = 1.0;  // where the approach ends (the ranger's --capture-m)
  double background_m = 50.0;       // returns at least this far are the far background
  double history_spacing_s = 0.25;  // approach plot: one sample per this much scan time at most
  size_t history_samples = 2400;    // per series (10 min at the spacing)
};

class SphereDisplayState {
 public:
  static constexpr int kRangeBins = 8;

  explicit SphereDisplayState(SphereDisplayOptions options = {});

  // now_us: wall clock when the message arrived (for ages in the JSON).
  // A line of a newer window, or the last line of its window, completes the
  // window being collected: it becomes the raster shown.
  void on_scan_line(const ScanLineView& line, int64_t now_us);
  void on_estimate(const EstimateView& estimate, int64_t now_us);
  void on_guidance(const GuidanceView& guidance, int64_t now_us);
  void on_truth(const TruthView& truth, int64_t now_us);

  // The page's state (without the raster's points).
  nlohmann::json to_json(int64_t now_us) const;
  // The newest complete raster: {window, half_extent_deg, range_lo_m,
  // range_hi_m, bins, points: [[azimuth deg, elevation deg, range m, bin], ...]}.
  nlohmann::json scan_json() const;

  // The newest complete raster's window, -1 before the first.
  int64_t scan_window() const { return raster_ ? raster_->window : -1; }

 private:
  struct Point {
    double azimuth_deg, elevation_deg, range_m;
    int bin;  // 0..kRangeBins-1, -1 = background
  };
  struct Raster {
    int64_t window = -1;
    double half_extent_deg = 0.0;
    int lines = 0;
    int no_return = 0;
    int background = 0;
    double range_lo_m = 0.0, range_hi_m = 0.0;
    std::vector<Point> points;
  };
  struct Sample {
    double t_s, range_m, lateral_m;
  };
  using Series = std::deque<Sample>;

  void complete_raster(int64_t now_us);
  void add_sample(Series& series, double t_s, const Vec3& p);
  void clear_history();

  SphereDisplayOptions options_;
  Raster collecting_;
  std::optional<Raster> raster_;
  int64_t raster_us_ = 0;
  int64_t lines_heard_ = 0;
  std::optional<EstimateView> estimate_;
  int64_t estimate_us_ = 0;
  int64_t estimates_failed_ = 0;
  std::optional<GuidanceView> guidance_;
  int64_t guidance_us_ = 0;
  std::optional<TruthView> truth_;
  int64_t truth_us_ = 0;
  std::optional<TruthView>
      last_verdict_;  // the newest judged approach (kept past the next one's start)
  Series estimate_history_, guidance_history_, truth_history_;
  int approach_ = -1;  // the approach the history is of (from the truth)
  int captured_ = 0, missed_ = 0;
  int last_judged_approach_ = -1;
};

}  // namespace ephor::sphere_display
