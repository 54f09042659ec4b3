#include "common/stripe/zero_reference_calibrator.h"

#include <cmath>
#include <numbers>

#include "common/stripe/least_squares.h"

namespace ephor::stripe {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// The fit's unknowns, in units that move the spot's image by comparable
// amounts (a mrad at the ~0.8 m of the arm is ~0.8 mm): zero references of
// joints 2-5 (mrad), C_T's rotation as a rotation vector applied on the
// right (mrad, camera frame), C_T's translation (mm, flange frame), the
// spot (mm, table frame).
constexpr int kParams = 12;
using Params = Eigen::Matrix<double, kParams, 1>;

struct Unpacked {
  TrueArm arm;
  Eigen::Isometry3d camera_in_flange;
  Eigen::Vector3d spot_mm;
};

Unpacked unpack(const Params& p, const TrueArm& model, const SensorCalibration& current) {
  ArmErrors e = model.errors();
  for (int j = 0; j < 4; ++j) e.zero_offset_rad[j + 1] += 1e-3 * p[j];
  Eigen::Isometry3d c = current.camera_in_flange;
  const Eigen::Vector3d rot = 1e-3 * p.segment<3>(4);
  if (rot.norm() > 0.0)
    c.linear() = c.linear() * Eigen::AngleAxisd(rot.norm(), rot.normalized()).toRotationMatrix();
  c.translation() += p.segment<3>(7);
  return {TrueArm(e), c, Eigen::Vector3d(p[10], p[11], 0.0)};
}

// The spot's predicted pixel minus the measured one, per sighting (px).
Eigen::VectorXd residuals(const Params& p, const std::vector<SpotSighting>& s,
                          const StripeWorkcell& cell, const TrueArm& model,
                          const SensorCalibration& current, double spot_radius_mm) {
  const Unpacked u = unpack(p, model, current);
  Eigen::VectorXd r(2 * s.size());
  for (size_t i = 0; i < s.size(); ++i) {
    const Eigen::Isometry3d cam =
        cell.base_in_table * u.arm.flange(s[i].joints) * u.camera_in_flange;
    r.segment<2>(2 * static_cast<Eigen::Index>(i)) =
        spot_centroid_px(cam, u.spot_mm, spot_radius_mm, current.camera) - s[i].spot_px;
  }
  return r;
}

// Mean table point (z = 0) of the lefty sightings' rays minus the righty
// ones' (mm): how far apart the two shoulder branches put the spot.
double lefty_righty_gap(const Params& p, const std::vector<SpotSighting>& s,
                        const StripeWorkcell& cell, const TrueArm& model,
                        const SensorCalibration& current) {
  const Unpacked u = unpack(p, model, current);
  Eigen::Vector2d sum[2] = {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  int n[2] = {0, 0};
  for (const SpotSighting& v : s) {
    const Eigen::Isometry3d cam = cell.base_in_table * u.arm.flange(v.joints) * u.camera_in_flange;
    const Eigen::Vector3d d = cam.linear() * current.camera.ray(v.spot_px.x(), v.spot_px.y());
    if (!(d.z() < -1e-6)) continue;
    const Eigen::Vector3d hit = cam.translation() - cam.translation().z() / d.z() * d;
    sum[v.lefty ? 1 : 0] += hit.head<2>();
    ++n[v.lefty ? 1 : 0];
  }
  if (n[0] == 0 || n[1] == 0) return 0.0;
  return (sum[1] / n[1] - sum[0] / n[0]).norm();
}

}  // namespace

Eigen::Vector2d spot_centroid_px(const Eigen::Isometry3d& cam, const Eigen::Vector3d& spot,
                                 double r, const CameraIntrinsics& k) {
  // The circle's conic carried into the image by the table-to-image
  // homography is the ellipse; its centre is the centroid.
  const Eigen::Isometry3d t = cam.inverse();  // table -> camera
  const Eigen::Vector3d pc = t * spot;
  // A spot behind the camera cannot be a sighting: a large penalty.
  if (!(pc.z() > 1.0)) return Eigen::Vector2d(1e4, 1e4);
  if (!(r > 0.0)) return k.project(pc);
  Eigen::Matrix3d kk;
  kk << k.fx_px, 0.0, k.cx_px, 0.0, k.fy_px, k.cy_px, 0.0, 0.0, 1.0;
  Eigen::Matrix3d h;  // (x - sx, y - sy, 1) on the table -> image
  h.col(0) = t.linear().col(0);
  h.col(1) = t.linear().col(1);
  h.col(2) = pc;
  h = kk * h;
  const Eigen::Matrix3d hi = h.inverse();
  const Eigen::Matrix3d circle = Eigen::Vector3d(1.0, 1.0, -r * r).asDiagonal();
  const Eigen::Matrix3d q = hi.transpose() * circle * hi;
  return -q.topLeftCorner<2, 2>().inverse() * q.topRightCorner<2, 1>();
}

ZeroReferenceCalibrator::ZeroReferenceCalibrator(StripeWorkcell cell, ZeroReferenceOptions options)
    : cell_(cell), options_(std::move(options)) {}

std::vector<arm::Joints> ZeroReferenceCalibrator::plan(const TrueArm& model,
                                                       const SensorCalibration& current,
                                                       const Eigen::Vector2d& spot_mm) const {
  static const arm::Puma560 puma(0.0);
  const Eigen::Vector3d spot(spot_mm.x(), spot_mm.y(), 0.0);
  std::vector<arm::Joints> out;
  size_t pose = 0;
  for (double dist : options_.distances_mm)
    for (double tilt_deg : options_.tilts_deg)
      for (int a = 0; a < (tilt_deg == 0.0 ? 1 : options_.azimuths); ++a)
        for (double roll_deg : options_.rolls_deg) {
          const double az = 2.0 * std::numbers::pi * a / std::max(1, options_.azimuths);
          const double tilt = tilt_deg * kDeg, roll = roll_deg * kDeg;
          const Eigen::Vector3d eye =
              spot + dist * Eigen::Vector3d(std::sin(tilt) * std::cos(az),
                                            std::sin(tilt) * std::sin(az), std::cos(tilt));
          const Eigen::Vector3d hint(std::cos(az + roll + std::numbers::pi / 2),
                                     std::sin(az + roll + std::numbers::pi / 2), 0.0);
          const int turn = static_cast<int>(pose++ % 8);
          const double off = turn % 2 == 0 ? 0.0 : options_.aim_offset_mm;
          const double off_az = std::numbers::pi / 2 * (turn / 2);
          const Eigen::Vector3d aim =
              spot + off * Eigen::Vector3d(std::cos(off_az), std::sin(off_az), 0.0);
          const Eigen::Isometry3d cam = look_at(eye, aim, hint);
          const Eigen::Isometry3d flange_in_base =
              cell_.base_in_table.inverse() * cam * current.camera_in_flange.inverse();
          // Every branch: righty and lefty, elbow up and down, wrist flipped
          // (or only the working configuration's).
          std::vector<arm::Joints> solutions;
          if (options_.working_branch_only) {
            if (const auto q =
                    puma.nearest_inverse(flange_in_base, StripeWorkcell::reference_joints() +
                                                             model.errors().zero_offset_rad))
              solutions.push_back(*q);
          } else {
            solutions = puma.inverse(flange_in_base);
          }
          for (const arm::Joints& physical : solutions) {
            const auto frames = puma.link_frames(physical);
            bool clear = true;
            for (int f = 2; f <= 6; ++f)
              if ((cell_.base_in_table * frames[f].translation()).z() < options_.min_clearance_mm)
                clear = false;
            if (clear) out.push_back(physical - model.errors().zero_offset_rad);
          }
        }
  return out;
}

std::vector<SpotSighting> ZeroReferenceCalibrator::sight(CalibrationRig& rig, const TrueArm& model,
                                                         const SensorCalibration& current,
                                                         const Eigen::Vector2d& spot_mm) const {
  std::vector<SpotSighting> out;
  std::vector<arm::Joints> views = plan(model, current, spot_mm);
  if (options_.order_for_travel) {
    // A short round from the working configuration and back.
    std::vector<arm::Joints> ordered;
    for (size_t k : short_round(views, StripeWorkcell::reference_joints()))
      ordered.push_back(views[k]);
    views = std::move(ordered);
  }
  for (const arm::Joints& q : views) {
    const auto s = find_spot(rig.spot_image(q));
    if (!s) continue;
    const arm::Joints at = rig.readings(q);
    const double q2 = at[1] + model.errors().zero_offset_rad[1];
    out.push_back({at, *s, std::cos(q2) > 0.0});
  }
  return out;
}

ZeroReferenceResult ZeroReferenceCalibrator::calibrate(CalibrationRig& rig, const TrueArm& model,
                                                       const SensorCalibration& current) const {
  std::vector<SpotSighting> all = sight(rig, model, current, options_.spot_guess_mm);
  if (static_cast<int>(all.size()) < options_.min_views)
    throw CalibrationError("zero references: the spot was seen in only " +
                           std::to_string(all.size()) + " views (need " +
                           std::to_string(options_.min_views) + ")");
  ZeroReferenceResult r = fit(all, model, current);
  for (int round = 1; round < options_.rounds; ++round) {
    // Re-plan with what was found: the spot lands nearer the centre, so
    // views lost at the image border before are now made.
    const std::vector<SpotSighting> more =
        sight(rig, TrueArm::with_zero_offsets(r.zero_offset_rad), r.updated, r.spot_mm);
    all.insert(all.end(), more.begin(), more.end());
    r = fit(all, model, current);
  }
  return r;
}

ZeroReferenceResult ZeroReferenceCalibrator::fit(const std::vector<SpotSighting>& sightings,
                                                 const TrueArm& model,
                                                 const SensorCalibration& current) const {
  if (static_cast<int>(sightings.size()) < options_.min_views)
    throw CalibrationError("zero references: " + std::to_string(sightings.size()) +
                           " sightings (need " + std::to_string(options_.min_views) + ")");
  Params p = Params::Zero();
  p[10] = options_.spot_guess_mm.x();
  p[11] = options_.spot_guess_mm.y();
  ZeroReferenceResult r;
  r.lefty_righty_gap_before_mm = lefty_righty_gap(p, sightings, cell_, model, current);
  const LeastSquaresResult ls = solve_least_squares(
      [&](const Eigen::VectorXd& x) {
        return residuals(Params(x), sightings, cell_, model, current, options_.spot_radius_mm);
      },
      p);
  if (!std::isfinite(ls.cost))
    throw CalibrationError("zero references: the least-squares fit diverged");
  p = ls.x;
  r.condition = ls.condition;
  const Eigen::VectorXd& res = ls.residuals;
  const Unpacked u = unpack(p, model, current);
  r.zero_offset_rad = u.arm.errors().zero_offset_rad;
  r.correction_rad = r.zero_offset_rad - model.errors().zero_offset_rad;
  r.updated = current;
  r.updated.camera_in_flange = u.camera_in_flange;
  r.spot_mm = u.spot_mm.head<2>();
  r.sightings = sightings.size();
  r.sightings_used = sightings;
  for (const SpotSighting& s : sightings) r.lefty_sightings += s.lefty ? 1 : 0;
  r.iterations = ls.iterations;
  r.rms_px = std::sqrt(ls.cost / static_cast<double>(sightings.size()));
  for (Eigen::Index i = 0; i + 1 < res.size(); i += 2)
    r.max_px = std::max(r.max_px, res.segment<2>(i).norm());
  r.lefty_righty_gap_after_mm = lefty_righty_gap(p, sightings, cell_, model, current);
  return r;
}

}  // namespace ephor::stripe
