// Fuzz target (issue 18): ephor-rambo-predictor's fit task on any stream of
// RAMBO_POSE (rambo_pose_t) with its clock: each message decoded the way the
// bus does (a message that does not decode to its full size is dropped) and
// taken by PoseFitter::on_pose() (predictor_task.h) with the process's
// defaults (a 4 s window, 5 poses, 3 px, refit after 10 outliers of 40 mm or
// 15 deg), the model as --carrier / --motion-model / --poly-degree /
// --poly-rotation choose it, the built-in target's principal moments, on a
// wall clock that moves by 0-1 s a message. Every RAMBO_PREDICTION it would
// publish must encode and be finite (every field, the polynomial's
// coefficients too), its uncertainties non-negative and, when fitted, its
// orientation a unit quaternion: the pose process and the planner take it.
//
// Input: a byte of settings (bit 0: the polynomial fits, as --carrier rm501;
// bit 1: their rotation as a rotation vector; bits 2-4: --poly-degree, mod 6),
// then up to 256 messages, each two bytes of clock step (little-endian,
// x 16 us), a 2-byte length (little-endian) and that many bytes. Seeds:
// fuzz_corpus/rambo_predictor (a target tumbling at 20 deg/s and drifting
// 30 mm/s, posed at 5 Hz for 3 s, with a wrong pose turned half round among
// them, for each model; made by a small generator).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include <spdlog/spdlog.h>

#include "common/fuzz/fuzz_input.h"
#include "common/rambo/rambo_cell.h"
#include "common/rambo/target_model_file.h"
#include "procs/rambo/predictor/predictor_task.h"

namespace {

using namespace ephor;
using namespace ephor::rambo;

template <std::size_t N>
bool finite(const double (&v)[N]) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

void check(const rambo_prediction_t& p) {
  if (!finite(p.position_mm) || !finite(p.velocity_mm_s) || !finite(p.orientation_wxyz) ||
      !finite(p.body_rates_rad_s) || !finite(p.principal_moments) || !finite(p.poly_r_mid_wxyz) ||
      !finite(p.poly_coeff) || !std::isfinite(p.poly_t_mid_s) || !std::isfinite(p.poly_t_scale_s) ||
      !std::isfinite(p.rms_rotation_residual_rad))
    fuzz::fail("a prediction that is not finite");
  if (!(p.position_sigma_mm >= 0.0) || !(p.rotation_sigma_rad >= 0.0) ||
      !std::isfinite(p.position_sigma_mm) || !std::isfinite(p.rotation_sigma_rad))
    fuzz::fail("a prediction's uncertainty that is negative or not finite");
  if (p.fitted) {
    const Eigen::Vector4d q(p.orientation_wxyz[0], p.orientation_wxyz[1], p.orientation_wxyz[2],
                            p.orientation_wxyz[3]);
    if (std::abs(q.norm() - 1.0) > 1e-6) fuzz::fail("a fitted orientation that is not a unit one");
  }
  const int size = p.getEncodedSize();
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  if (p.encode(bytes.data(), 0, size) != size) fuzz::fail("the prediction does not encode");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // The task's log lines (a new status, a re-fit) would only slow the run.
  static const bool quiet = [] {
    spdlog::set_level(spdlog::level::off);
    return true;
  }();
  (void)quiet;
  static const Eigen::Vector3d moments = cell_from_flags("", 0).principal_moments;
  if (size < 1) return 0;
  PoseFitterOptions options;
  options.polynomial = (data[0] & 1) != 0;
  options.poly_rotation =
      (data[0] & 2) != 0 ? RotationCoordinates::kRotationVector : RotationCoordinates::kZyxAngles;
  options.poly_degree = ((data[0] >> 2) & 7) % 6;
  options.principal_moments = moments;
  PoseFitter fitter(options);
  int64_t now_us = 1'700'000'000'000'000;
  size_t at = 1;
  for (int k = 0; k < 256 && at + 4 <= size; ++k) {
    now_us += 16 * static_cast<int64_t>(data[at] | (data[at + 1] << 8));
    const size_t len = data[at + 2] | (static_cast<size_t>(data[at + 3]) << 8);
    at += 4;
    if (len > size - at) break;
    const int n = static_cast<int>(len);
    rambo_pose_t m;
    const bool whole = m.decode(data + at, 0, n) == n;
    at += len;
    if (!whole) continue;
    if (const std::optional<rambo_prediction_t> out = fitter.on_pose(m, now_us)) check(*out);
  }
  return 0;
}
