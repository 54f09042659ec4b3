// Fuzz target (issue 18): ephor-sphere-guidance's guide task on any stream
// of SPHERE_ESTIMATE messages (its only input): each decoded as
// sphere_estimate_t the way the bus does (a message that does not decode to
// its full size is dropped), kept in the task's one-message mailbox (a
// message not taken before the next one arrives is overwritten, as when the
// task runs late), estimate_input_of(), SphereGuidance::on_estimate() with
// the process's defaults (or --window-s 0.1 and --min-updates 1, within its
// flags' ranges) and every answer as guidance_message_of() publishes it. The
// guidance has no clock of its own: time is the messages' scan clock.
// A refused estimate must be counted as a bad input; a command must be
// finite, change the chaser's velocity by at most max_accel * window (the
// chaser's own limit, ApproachConfig) and, without a track, hold it; the
// published state must be finite; the message must encode.
//
// Input: one byte choosing the configuration (bit 0: --window-s 0.1, bit 1:
// --min-updates 1), then up to 128 messages, each a flags byte (bit 0: the
// guide task runs before the next message arrives; otherwise the next one
// overwrites it), a 2-byte little-endian length and that many bytes.
// Seeds: fuzz_corpus/sphere_guidance (a sphere closing from 20 m, from 3 m
// and near capture; windows with no estimate, a repeat, a message
// overwritten and a ranger's restart) and the inputs of the faults it found
// (crash-*: a sphere 4.9e285 m away, windows 2^63 apart).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "common/fuzz/fuzz_input.h"
#include "common/sphere/guidance/sphere_guidance.h"
#include "ephor/sphere_estimate_t.hpp"
#include "ephor/sphere_guidance_t.hpp"
#include "procs/sphere/guidance/guidance_messages.h"

namespace {

using namespace ephor;
using namespace ephor::sphere;

// The guide task with one message from the mailbox.
void guide(SphereGuidance& guidance, const GuidanceConfig& config, const sphere_estimate_t& m) {
  const int bad_before = guidance.bad_inputs();
  const Eigen::Vector3d before = guidance.chaser_velocity();
  const std::optional<GuidanceOutput> out = guidance.on_estimate(estimate_input_of(m));
  if (!out) {
    if (guidance.bad_inputs() != bad_before + 1) fuzz::fail("an estimate dropped uncounted");
    if (guidance.chaser_velocity() != before) fuzz::fail("a refused estimate moved the chaser");
    return;
  }
  if (guidance.bad_inputs() != bad_before) fuzz::fail("an estimate used and counted bad");
  const Eigen::Vector3d& v = out->command.chaser_velocity_m_s;
  if (!v.allFinite()) fuzz::fail("a chaser velocity command that is not finite");
  const double budget = config.approach.max_accel_m_s2 * config.approach.window_s;
  if ((v - before).norm() > budget * (1.0 + 1e-9) + 1e-12)
    fuzz::fail("a velocity change beyond the chaser's acceleration limit");
  if (!out->tracking && v != before) fuzz::fail("the chaser moved without a track");
  if (guidance.chaser_velocity() != v) fuzz::fail("the command is not the velocity kept");
  sphere_guidance_t g = guidance_message_of(*out, guidance, config);
  g.utime = 1'700'000'000'000'000;
  if (!std::isfinite(g.apply_t_s) || !fuzz::all_finite(g.chaser_velocity_m_s, 3) ||
      !std::isfinite(g.t_s) || !fuzz::all_finite(g.position_m, 3) ||
      !fuzz::all_finite(g.velocity_m_s, 3) || !fuzz::all_finite(g.position_sigma_m, 3) ||
      !fuzz::all_finite(g.velocity_sigma_m_s, 3) || !std::isfinite(g.range_to_capture_m))
    fuzz::fail("a SPHERE_GUIDANCE that is not finite");
  if (g.phase < sphere_guidance_t::PHASE_ACQUIRE || g.phase > sphere_guidance_t::PHASE_FINAL)
    fuzz::fail("a phase out of range");
  const int size = g.getEncodedSize();
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  if (g.encode(bytes.data(), 0, size) != size) fuzz::fail("the guidance does not encode");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  GuidanceConfig config;
  if ((data[0] & 1) != 0) config.approach.window_s = 0.1;
  if ((data[0] & 2) != 0) config.min_updates = 1;
  SphereGuidance guidance(config);
  std::optional<sphere_estimate_t> mailbox;
  size_t at = 1;
  for (int k = 0; k < 128 && at + 3 <= size; ++k) {
    const bool task_runs = (data[at] & 1) != 0;
    const size_t len = data[at + 1] | (static_cast<size_t>(data[at + 2]) << 8);
    at += 3;
    if (len > size - at) break;
    sphere_estimate_t m;
    const int n = static_cast<int>(len);
    const bool whole = m.decode(data + at, 0, n) == n;
    at += len;
    if (!whole) continue;  // the bus counts a decode error
    mailbox = m;           // overwrites one not taken yet
    if (!task_runs) continue;
    guide(guidance, config, *mailbox);
    mailbox.reset();
  }
  if (mailbox) guide(guidance, config, *mailbox);
  return 0;
}
