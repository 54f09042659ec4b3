// Fuzz target (issue 18): ephor-sphere-ranger (RangerProcess,
// ranger_messages.h, on its RangerWorld) on any stream of SPHERE_GUIDANCE
// messages (sphere_guidance_t, its only input), with its tasks released as
// the runtime would: each message decoded as the bus does (a message that
// does not decode to its full size is dropped) and handed to
// RangerProcess::on_guidance(); on a fake scan clock that each record's step
// moves, the task "scan" every 5 ms (RangerProcess::scan: the world advanced,
// its lines and verdicts as published) and "truth" every 50 ms
// (RangerProcess::truth). Settings within the process's flags: the sphere
// starting 20 m out (the default) or 1.5 m out (a verdict within seconds),
// --background, --window-s 0.5 or 0.1, --approaches 1 or 3, --max-s 0 or 2.
//
// Checked, as a user would:
//  - a command is refused exactly when its time or velocity is not finite,
//    and counted: commands + refused = the messages handed over;
//  - the chaser (the simulated actuator) changes velocity only at window
//    boundaries and by at most max_accel * window per window, whatever is
//    commanded;
//  - SPHERE_SCAN_LINE: times, angles finite, ranges finite and positive or
//    NaN (no return), line ids increasing, windows not decreasing, the frame
//    within max_half_extent_deg, arrays num_pulses long; it encodes;
//  - SPHERE_TRUTH (approach and verdict): every number finite (but the
//    approach's capture_t_s, NaN), no more verdicts than approaches; encodes.
//
// Input: a byte of settings (bit 0: --start-m 1.5; bit 1: --background;
// bit 2: --window-s 0.1; bit 3: --approaches 3; bit 4: --max-s 2), then a
// FuzzMessageStream (common/fuzz/fuzz_input.h) of up to 256 messages of up
// to 4096 bytes, every channel SPHERE_GUIDANCE; the scan clock stops at
// kMaxScanS (each window ray-casts a raster of 10 kHz pulses). Seeds:
// fuzz_corpus/sphere_ranger (guidance closing from 20 m, braking to capture
// from 1.5 m, repeated and refused commands, commands for windows long past
// and far ahead; made by a small generator); crash-* are the inputs of the
// faults it found.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include "common/fuzz/fuzz_input.h"
#include "common/sphere/world/ranger_world.h"
#include "procs/sphere/ranger/ranger_messages.h"

namespace {

using namespace ephor;
using namespace ephor::sphere;

constexpr int64_t kWallStartUs = 1'700'000'000'000'000;
constexpr int64_t kScanUs = 5'000;
constexpr int64_t kTruthUs = 50'000;
constexpr int64_t kMaxScanUs = 6'000'000;  // kMaxScanS = 6 s

void check_truth(const sphere_truth_t& m, bool approach) {
  if (!std::isfinite(m.t_s) || !fuzz::all_finite(m.position_m, 3) ||
      !fuzz::all_finite(m.velocity_m_s, 3) || !fuzz::all_finite(m.chaser_velocity_m_s, 3) ||
      !fuzz::all_finite(m.target_velocity_m_s, 3) || !std::isfinite(m.half_extent_deg))
    fuzz::fail("SPHERE_TRUTH that is not finite");
  if (!approach && (!std::isfinite(m.capture_t_s) || !std::isfinite(m.capture_speed_m_s) ||
                    !std::isfinite(m.capture_offset_m)))
    fuzz::fail("a verdict that is not finite");
  fuzz::check_encodes(m, "SPHERE_TRUTH");
}

struct LineCheck {
  double max_half_extent_deg;
  int64_t last_line = -1;
  int64_t last_window = -1;

  void check(const sphere_scan_line_t& m) {
    const auto n = static_cast<size_t>(m.num_pulses);
    if (m.num_pulses < 0 || m.t_s.size() != n || m.azimuth_rad.size() != n ||
        m.elevation_rad.size() != n || m.range_m.size() != n)
      fuzz::fail("SPHERE_SCAN_LINE whose arrays are not num_pulses long");
    if (m.line <= last_line) fuzz::fail(fmt::format("line {} after {}", m.line, last_line));
    if (m.window < last_window)
      fuzz::fail(fmt::format("window {} after {}", m.window, last_window));
    last_line = m.line;
    last_window = m.window;
    if (!(m.half_extent_deg > 0.0f) ||
        static_cast<double>(m.half_extent_deg) > max_half_extent_deg + 1e-6)
      fuzz::fail(fmt::format("a frame of half extent {} deg", m.half_extent_deg));
    for (size_t i = 0; i < n; ++i) {
      if (!std::isfinite(m.t_s[i]) || !std::isfinite(m.azimuth_rad[i]) ||
          !std::isfinite(m.elevation_rad[i]))
        fuzz::fail("a pulse whose time or angles are not finite");
      if (!std::isnan(m.range_m[i]) && !(std::isfinite(m.range_m[i]) && m.range_m[i] > 0))
        fuzz::fail(fmt::format("a pulse with range {} m", m.range_m[i]));
    }
    fuzz::check_encodes(m, "SPHERE_SCAN_LINE");
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const bool quiet = [] {
    spdlog::set_level(spdlog::level::off);  // a verdict and every tenth refusal are logged
    return true;
  }();
  (void)quiet;
  if (size < 1) return 0;
  RangerWorldConfig config;
  const double start_m = (data[0] & 1) != 0 ? 1.5 : 20.0;
  config.motion.start_position_m = Eigen::Vector3d(0.0, 0.0, start_m);
  config.motion.target_velocity_m_s = RelativeMotionConfig::table1_drift(start_m);
  config.background.enabled = (data[0] & 2) != 0;
  if ((data[0] & 4) != 0) config.motion.window_s = 0.1;
  config.approaches = (data[0] & 8) != 0 ? 3 : 1;
  if ((data[0] & 16) != 0) config.max_s = 2.0;
  RangerWorld world(config);
  RangerProcess ranger(world, kWallStartUs);

  const double window_s = config.motion.window_s;
  const double max_change = config.motion.max_accel_m_s2 * window_s;
  LineCheck lines{config.max_half_extent_deg};
  Eigen::Vector3d chaser = world.motion().chaser_velocity();
  int64_t windows = world.windows_started();
  size_t verdicts = 0;
  int64_t clock_us = 0, next_scan = kScanUs, next_truth = kTruthUs;
  const auto run_until = [&](int64_t end_us) {
    for (;;) {
      const int64_t next = std::min(next_scan, next_truth);
      if (next > end_us) break;
      clock_us = next;
      const double t_s = static_cast<double>(clock_us) * 1e-6;
      if (next == next_scan) {
        next_scan += kScanUs;
        RangerProcess::Scan out = ranger.scan(t_s);
        // The chaser's burns: only at window starts, each within its limit.
        const int64_t started = world.windows_started() - windows;
        const Eigen::Vector3d& v = world.motion().chaser_velocity();
        if (!v.allFinite()) fuzz::fail("a chaser velocity that is not finite");
        if (started == 0 && v != chaser) fuzz::fail("the chaser changed velocity within a window");
        if ((v - chaser).norm() > static_cast<double>(started) * max_change * (1.0 + 1e-9) + 1e-12)
          fuzz::fail(
              fmt::format("the chaser's velocity changed by {} m/s over {} windows, above "
                          "its limit of {} m/s a window",
                          (v - chaser).norm(), started, max_change));
        chaser = v;
        windows = world.windows_started();
        for (const sphere_scan_line_t& m : out.lines) lines.check(m);
        for (const sphere_truth_t& m : out.verdicts) check_truth(m, false);
        verdicts += out.verdicts.size();
        if (verdicts > static_cast<size_t>(config.approaches))
          fuzz::fail(fmt::format("{} verdicts of {} approaches", verdicts, config.approaches));
      } else {
        next_truth += kTruthUs;
        if (const auto m = ranger.truth(t_s)) check_truth(*m, true);
      }
    }
    clock_us = end_us;
  };

  int64_t handed = 0;
  fuzz::FuzzMessageStream stream(data + 1, size - 1, 1);
  fuzz::FuzzMessage msg;
  while (!ranger.finished() && stream.next(msg)) {
    if (clock_us + msg.step_us > kMaxScanUs) break;
    run_until(clock_us + msg.step_us);
    sphere_guidance_t m;
    if (!msg.decode(m)) continue;
    const bool finite = std::isfinite(m.apply_t_s) && fuzz::all_finite(m.chaser_velocity_m_s, 3);
    const int64_t refused = ranger.commands_refused();
    if (ranger.on_guidance(m) != finite)
      fuzz::fail(finite ? "a finite command refused" : "a command that is not finite taken");
    ++handed;
    if (ranger.commands() + ranger.commands_refused() != handed)
      fuzz::fail("a command neither taken nor counted refused");
    if (!finite && ranger.commands_refused() != refused + 1) fuzz::fail("a refusal not counted");
  }
  // The scan task once more: lines already due come out.
  run_until(clock_us + kScanUs);
  return 0;
}
