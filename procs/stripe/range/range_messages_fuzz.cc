// Fuzz target (issue 18): ephor-stripe-range on any stream of its inputs,
// STRIPE_PROFILE and STRIPE_SCAN, with a clock: each message decoded the way
// the bus does (a message that does not decode to its full size is
// dropped); a profile as the range task takes it (range_profile(): stripe_of()
// refuses arrays that disagree with num_rows, rows that do not increase,
// numbers not finite; then RangeFinder::to_table() with the nominal arm and
// the drawing's cage, as without --calibration, in deploy/stripe/workcell.pbtxt;
// add_to_cloud() into the CloudAccumulator), a scan as its handler does
// (on_scan()), and the cloud task every 200 ms of the clock
// (CloudAccumulator::take_complete(), cloud_message_of(), remember_cloud()).
// Arbitrary profiles, not only those the stripe process makes.
// Every published point must be finite (mm, table frame, as float), the
// points' arrays as long as num_points, the scan's counts those of the
// stripes added (checked against a model kept here), a cloud's counts and
// bounding box those of its stripes; every message must encode.
//
// Input: up to 256 records, each a byte naming the channel (bit 0 clear:
// STRIPE_PROFILE, set: STRIPE_SCAN), two bytes of clock step (ms,
// little-endian: the cloud task runs at each 200 ms boundary passed), a
// 2-byte little-endian length and that many bytes of the message.
// Seeds: fuzz_corpus/stripe_range (a scan of three stripes ranged and
// captured, one with a stripe repeated and one never heard (the 5 s
// timeout), a profile whose rows do not increase, a CAPTURED said again).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "common/config/repo_paths.h"
#include "common/fuzz/fuzz_input.h"
#include "common/geometry/workcell_file.h"
#include "common/stripe/calibration_file.h"
#include "common/stripe/range_finder.h"
#include "ephor/stripe_cloud_t.hpp"
#include "ephor/stripe_points_t.hpp"
#include "ephor/stripe_profile_t.hpp"
#include "ephor/stripe_scan_t.hpp"
#include "procs/stripe/range/cloud_accumulator.h"
#include "procs/stripe/range/range_messages.h"

namespace {

using namespace ephor;
using namespace ephor::stripe;

const RangeFinder& finder() {
  static const RangeFinder f = [] {
    const geometry::Workcell workcell =
        geometry::load_workcell_file(resolve_repo_path("deploy/stripe/workcell.pbtxt"));
    const StripeCalibration calibration = calibration_from_flags("", 0);
    return RangeFinder(StripeWorkcell::from_workcell(workcell), calibration.arm_model(),
                       calibration.sensor);
  }();
  return f;
}

// What the accumulator should hold: points per stripe of each open scan.
struct Model {
  std::map<int64_t, std::map<int, int64_t>> scans;
  std::set<int64_t> finished;
};

void range_task(const stripe_profile_t& m, CloudAccumulator& clouds, Model& model) {
  std::string why;
  std::optional<RangedStripe> r = range_profile(m, finder(), &why);
  if (!r) {
    if (why.empty()) fuzz::fail("a profile refused without a reason");
    return;
  }
  const stripe_points_t& out = r->message;
  if (out.num_points < 0 || out.num_points > m.num_rows ||
      out.x_mm.size() != static_cast<size_t>(out.num_points) ||
      out.y_mm.size() != out.x_mm.size() || out.z_mm.size() != out.x_mm.size() ||
      r->points.size() != out.x_mm.size())
    fuzz::fail("STRIPE_POINTS arrays that disagree with num_points");
  for (size_t i = 0; i < out.x_mm.size(); ++i)
    if (!std::isfinite(out.x_mm[i]) || !std::isfinite(out.y_mm[i]) || !std::isfinite(out.z_mm[i]) ||
        !r->points[i].allFinite())
      fuzz::fail("a published point that is not finite");
  const auto n = static_cast<int64_t>(r->points.size());
  const bool expect_added = m.scan_id > 0 && m.stripe_index >= 0 &&
                            model.finished.count(m.scan_id) == 0 &&
                            model.scans[m.scan_id].count(m.stripe_index) == 0;
  if (add_to_cloud(*r, clouds) != expect_added) fuzz::fail("a stripe added or not, wrongly");
  if (expect_added) model.scans[m.scan_id][m.stripe_index] = n;
  int64_t points = 0;
  int stripes = 0;
  if (const auto it = model.scans.find(m.scan_id); it != model.scans.end()) {
    for (const auto& [index, k] : it->second) points += k;
    stripes = static_cast<int>(it->second.size());
    if (it->second.empty()) model.scans.erase(it);
  }
  if (out.scan_stripes != stripes || out.scan_points != points)
    fuzz::fail("the scan's counts in STRIPE_POINTS are not its stripes'");
  fuzz::check_encodes(out, "STRIPE_POINTS");
}

void cloud_task(CloudAccumulator& clouds, FinishedClouds& finished, Model& model, double now_s) {
  for (const CompletedCloud& c : clouds.take_complete(now_s)) {
    const auto it = model.scans.find(c.scan_id);
    if (it == model.scans.end() && c.stripes != 0) fuzz::fail("a cloud of an unknown scan");
    int64_t points = 0;
    if (it != model.scans.end()) {
      for (const auto& [index, k] : it->second) points += k;
      if (c.stripes != static_cast<int>(it->second.size()))
        fuzz::fail("a cloud's stripes are not those added");
      model.scans.erase(it);
    }
    model.finished.insert(c.scan_id);
    stripe_cloud_t m = cloud_message_of(c);
    m.utime = 1'700'000'000'000'000;
    if (m.points != points || m.points != static_cast<int64_t>(c.points.size()))
      fuzz::fail("a cloud's points are not its stripes'");
    if (m.stripes_missing < 0) fuzz::fail("negative missing stripes");
    for (int i = 0; i < 3; ++i)
      if (!std::isfinite(m.bbox_mm[i]) || !std::isfinite(m.bbox_mm[3 + i]) ||
          m.bbox_mm[i] > m.bbox_mm[3 + i])
        fuzz::fail("a cloud's bounding box not finite or inside out");
    for (const Eigen::Vector3d& p : c.points)
      for (int i = 0; i < 3; ++i)
        if (!(p[i] >= m.bbox_mm[i] && p[i] <= m.bbox_mm[3 + i]))
          fuzz::fail("a cloud point outside its bounding box");
    fuzz::check_encodes(m, "STRIPE_CLOUD");
    remember_cloud(finished, m);
    if (finished.size() > kFinishedCloudsKept) fuzz::fail("too many clouds kept");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  CloudAccumulator clouds(5.0);  // --missing-timeout-s's default
  FinishedClouds finished;
  Model model;
  int64_t now_ms = 1'000'000;  // the process's monotonic clock
  size_t at = 0;
  for (int k = 0; k < 256 && at + 5 <= size; ++k) {
    const bool scan_message = (data[at] & 1) != 0;
    const int64_t step_ms = data[at + 1] | (data[at + 2] << 8);
    const size_t len = data[at + 3] | (static_cast<size_t>(data[at + 4]) << 8);
    at += 5;
    // The cloud task at each 200 ms boundary passed.
    for (int64_t t = (now_ms / 200 + 1) * 200; t <= now_ms + step_ms; t += 200)
      cloud_task(clouds, finished, model, static_cast<double>(t) * 1e-3);
    now_ms += step_ms;
    if (len > size - at) break;
    const int n = static_cast<int>(len);
    const uint8_t* bytes = data + at;
    at += len;
    if (scan_message) {
      stripe_scan_t m;
      if (m.decode(bytes, 0, n) != n) continue;
      stripe_cloud_t* again = on_scan(m, clouds, finished, static_cast<double>(now_ms) * 1e-3);
      if (again) {
        if (m.state != stripe_scan_t::STATE_CAPTURED || again->scan_id != m.scan_id)
          fuzz::fail("a cloud said again for the wrong scan");
        fuzz::check_encodes(*again, "the STRIPE_CLOUD said again");
      }
      continue;
    }
    stripe_profile_t m;
    if (m.decode(bytes, 0, n) != n) continue;
    range_task(m, clouds, model);
  }
  return 0;
}
