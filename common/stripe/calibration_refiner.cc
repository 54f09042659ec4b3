#include "common/stripe/calibration_refiner.h"

#include <cmath>
#include <numbers>

#include "common/stripe/least_squares.h"
#include "common/stripe/stripe_extractor.h"

namespace ephor::stripe {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Unknowns (scaled so each moves the residuals comparably): joints 2-5
// zero references (mrad); C_T rotation vector on the right (mrad, camera
// frame) and translation (mm, flange frame); the light plane turned about
// S's y and z axes (mrad; a turn about its normal x changes nothing) and
// moved along x (mm); the spot (mm, table frame).
// With link_errors, links 1-5's d and a (mm) and alpha (mrad) follow.
constexpr int kParams = 15;
constexpr int kLinkParams = 15;

struct Model {
  TrueArm arm;
  SensorCalibration cal;
  Eigen::Vector3d spot_mm;
};

Eigen::Matrix3d turn(const Eigen::Vector3d& rot) {
  const double a = rot.norm();
  return a > 0.0 ? Eigen::AngleAxisd(a, rot / a).toRotationMatrix() : Eigen::Matrix3d::Identity();
}

Model unpack(const Eigen::VectorXd& p, const TrueArm& model, const SensorCalibration& current) {
  ArmErrors e = model.errors();
  for (int j = 0; j < 4; ++j) e.zero_offset_rad[j + 1] += 1e-3 * p[j];
  if (p.size() == kParams + kLinkParams)
    for (int i = 0; i < 5; ++i) {
      e.dh_error[i].d_mm += p[kParams + 3 * i];
      e.dh_error[i].a_mm += p[kParams + 3 * i + 1];
      e.dh_error[i].alpha_rad += 1e-3 * p[kParams + 3 * i + 2];
    }
  SensorCalibration c = current;
  c.camera_in_flange.linear() = c.camera_in_flange.linear() * turn(1e-3 * p.segment<3>(4));
  c.camera_in_flange.translation() += p.segment<3>(7);
  c.projector_in_flange.linear() =
      c.projector_in_flange.linear() * turn(Eigen::Vector3d(0.0, 1e-3 * p[10], 1e-3 * p[11]));
  c.projector_in_flange.translation() += p[12] * c.projector_in_flange.linear().col(0);
  return {TrueArm(e), c, Eigen::Vector3d(p[13], p[14], 0.0)};
}

// Stripe points' heights above the table (mm, table frame), the camera ray
// met with the light plane; a ray nearly in the plane gives a large value.
void table_heights(const Model& m, const StripeWorkcell& cell, const TableStripeView& v,
                   Eigen::Ref<Eigen::VectorXd> out) {
  const Eigen::Isometry3d t = cell.base_in_table * m.arm.flange(v.joints);
  const Eigen::Isometry3d c = t * m.cal.camera_in_flange;
  const Eigen::Isometry3d s = t * m.cal.projector_in_flange;
  const Eigen::Vector3d n = s.linear().col(0);
  for (size_t i = 0; i < v.points_px.size(); ++i) {
    const Eigen::Vector3d d = c.linear() * m.cal.camera.ray(v.points_px[i].x(), v.points_px[i].y());
    const double den = n.dot(d);
    if (std::abs(den) < 1e-9) {
      out[static_cast<Eigen::Index>(i)] = 1e3;
      continue;
    }
    const double lambda = n.dot(s.translation() - c.translation()) / den;
    out[static_cast<Eigen::Index>(i)] = (c.translation() + lambda * d).z();
  }
}

}  // namespace

CalibrationRefiner::CalibrationRefiner(StripeWorkcell cell, CalibrationRefinerOptions options)
    : cell_(cell), options_(std::move(options)) {}

CalibrationRefinement CalibrationRefiner::refine(CalibrationRig& rig, const TrueArm& model,
                                                 const SensorCalibration& current,
                                                 const std::vector<SpotSighting>& spots,
                                                 const Eigen::Vector2d& spot_guess_mm) const {
  StripeExtractor extractor;
  std::vector<TableStripeView> views;
  arm::Joints near = StripeWorkcell::reference_joints();
  std::vector<Eigen::Vector3d> approaches = {Eigen::Vector3d::UnitZ()};
  for (int k = 0; k < options_.azimuths; ++k) {
    const double az = 2.0 * std::numbers::pi * k / options_.azimuths;
    const double tilt = options_.tilt_deg * kDeg;
    approaches.emplace_back(std::sin(tilt) * std::cos(az), std::sin(tilt) * std::sin(az),
                            std::cos(tilt));
  }
  std::vector<Eigen::Isometry3d> stripe_flanges;
  for (const Eigen::Vector2d& centre : options_.centres_mm)
    for (const Eigen::Vector3d& approach : approaches)
      for (int along = 0; along < 2; ++along)
        for (double dist : options_.distances_mm) {
          const Eigen::Vector3d hint =
              along == 0 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
          const Eigen::Isometry3d s = projector_looking_at(
              Eigen::Vector3d(centre.x(), centre.y(), 0.0), approach, dist, hint);
          stripe_flanges.push_back(flange_for_projector(s, current));
        }
  for (const auto& [index, q] :
       visiting_order(cell_, stripe_flanges, near, model.errors().zero_offset_rad,
                      options_.order_for_travel)) {
    near = q;
    const Stripe stripe = extractor.extract(rig.stripe_image(q));
    TableStripeView v{rig.readings(q), {}};
    for (size_t i = 0; i < stripe.points.size();
         i += static_cast<size_t>(std::max(1, options_.rows_step)))
      v.points_px.emplace_back(stripe.points[i].u_px, stripe.points[i].row);
    if (!v.points_px.empty()) views.push_back(std::move(v));
  }
  // The spot from the working configuration.
  std::vector<SpotSighting> all_spots;
  if (options_.use_all_branch_sightings) all_spots = spots;
  const Eigen::Vector3d spot(spot_guess_mm.x(), spot_guess_mm.y(), 0.0);
  std::vector<Eigen::Isometry3d> spot_flanges;
  int pose = 0;
  for (double dist : options_.spot_distances_mm)
    for (int a = 0; a <= options_.spot_azimuths; ++a)
      for (double roll_deg : options_.spot_rolls_deg) {
        // a == 0: straight down; else tilted towards azimuth a.
        const double az = 2.0 * std::numbers::pi * a / std::max(1, options_.spot_azimuths);
        const double tilt = a == 0 ? 0.0 : options_.tilt_deg * kDeg;
        const Eigen::Vector3d eye =
            spot + dist * Eigen::Vector3d(std::sin(tilt) * std::cos(az),
                                          std::sin(tilt) * std::sin(az), std::cos(tilt));
        const int k = pose++ % 8;
        const double off = k % 2 == 0 ? 0.0 : options_.aim_offset_mm;
        const double off_az = std::numbers::pi / 2 * (k / 2);
        const Eigen::Vector3d aim =
            spot + off * Eigen::Vector3d(std::cos(off_az), std::sin(off_az), 0.0);
        const double r = az + roll_deg * kDeg + std::numbers::pi / 2;
        const Eigen::Isometry3d cam =
            look_at(eye, aim, Eigen::Vector3d(std::cos(r), std::sin(r), 0.0));
        spot_flanges.push_back(cam * current.camera_in_flange.inverse());
      }
  // From the working configuration (as listed), or on from the last stripe view.
  for (const auto& [index, q] :
       visiting_order(cell_, spot_flanges,
                      options_.order_for_travel ? near : StripeWorkcell::reference_joints(),
                      model.errors().zero_offset_rad, options_.order_for_travel)) {
    const auto px = find_spot(rig.spot_image(q));
    if (!px) continue;
    const arm::Joints at = rig.readings(q);
    const double q2 = at[1] + model.errors().zero_offset_rad[1];
    all_spots.push_back({at, *px, std::cos(q2) > 0.0});
  }
  return fit(views, all_spots, model, current, spot_guess_mm);
}

CalibrationRefinement CalibrationRefiner::fit(const std::vector<TableStripeView>& stripes,
                                              const std::vector<SpotSighting>& spots,
                                              const TrueArm& model,
                                              const SensorCalibration& current,
                                              const Eigen::Vector2d& spot_guess_mm) const {
  size_t points = 0;
  for (const auto& v : stripes) points += v.points_px.size();
  if (points < static_cast<size_t>(options_.min_stripe_points))
    throw CalibrationError("refinement: only " + std::to_string(points) +
                           " stripe points seen on the table (need " +
                           std::to_string(options_.min_stripe_points) + ")");
  const Eigen::Index n_spot = 2 * static_cast<Eigen::Index>(spots.size());
  const Eigen::Index n = n_spot + static_cast<Eigen::Index>(points);
  // Unweighted residuals: spot pixels, then stripe heights (mm).
  auto raw = [&](const Eigen::VectorXd& p) {
    const Model m = unpack(p, model, current);
    Eigen::VectorXd r(n);
    for (size_t i = 0; i < spots.size(); ++i) {
      const Eigen::Isometry3d cam =
          cell_.base_in_table * m.arm.flange(spots[i].joints) * m.cal.camera_in_flange;
      r.segment<2>(2 * static_cast<Eigen::Index>(i)) =
          spot_centroid_px(cam, m.spot_mm, options_.spot_radius_mm, m.cal.camera) -
          spots[i].spot_px;
    }
    Eigen::Index k = n_spot;
    for (const auto& v : stripes) {
      const auto len = static_cast<Eigen::Index>(v.points_px.size());
      table_heights(m, cell_, v, r.segment(k, len));
      k += len;
    }
    return r;
  };
  // With the link errors free, several combinations of them (and of the
  // zero references of the parallel joints 2 and 3) move nothing the views
  // can see, or move the whole world with the spot: a prior of the links'
  // tolerances keeps them near the drawing's values.
  const Eigen::Index n_prior = options_.link_errors ? kLinkParams : 0;
  auto weighted = [&](const Eigen::VectorXd& p) {
    Eigen::VectorXd r(n + n_prior);
    r.head(n) = raw(p);
    r.head(n_spot) /= options_.spot_sigma_px;
    r.segment(n_spot, n - n_spot) /= options_.table_sigma_mm;
    for (Eigen::Index i = 0; i < n_prior; ++i)
      r[n + i] = p[kParams + i] / (i % 3 == 2 ? 1e3 * options_.link_twist_prior_deg * kDeg
                                              : options_.link_length_prior_mm);
    return r;
  };
  Eigen::VectorXd p0 = Eigen::VectorXd::Zero(kParams + (options_.link_errors ? kLinkParams : 0));
  p0[13] = spot_guess_mm.x();
  p0[14] = spot_guess_mm.y();
  CalibrationRefinement out;
  auto report = [&](const Eigen::VectorXd& r, double& spot_rms, double& table_rms) {
    spot_rms = n_spot > 0 ? std::sqrt(r.head(n_spot).squaredNorm() / (n_spot / 2)) : 0.0;
    table_rms = std::sqrt(r.tail(n - n_spot).squaredNorm() / static_cast<double>(n - n_spot));
  };
  report(raw(p0), out.spot_rms_before_px, out.table_rms_before_mm);
  const LeastSquaresResult ls = solve_least_squares(weighted, p0);
  if (!std::isfinite(ls.cost)) throw CalibrationError("refinement: the fit diverged");
  const Eigen::VectorXd r = raw(ls.x);
  report(r, out.spot_rms_px, out.table_rms_mm);
  for (Eigen::Index i = 0; i + 1 < n_spot; i += 2)
    out.spot_max_px = std::max(out.spot_max_px, r.segment<2>(i).norm());
  out.table_max_mm = r.tail(n - n_spot).cwiseAbs().maxCoeff();
  const Model m = unpack(ls.x, model, current);
  out.zero_offset_rad = m.arm.errors().zero_offset_rad;
  out.arm = m.arm;
  out.correction_rad = out.zero_offset_rad - model.errors().zero_offset_rad;
  out.updated = m.cal;
  out.spot_mm = m.spot_mm.head<2>();
  out.camera_change_mm =
      (m.cal.camera_in_flange.translation() - current.camera_in_flange.translation()).norm();
  out.camera_change_deg = Eigen::AngleAxisd(m.cal.camera_in_flange.linear().transpose() *
                                            current.camera_in_flange.linear())
                              .angle() /
                          kDeg;
  const Eigen::Vector3d n_old = current.projector_in_flange.linear().col(0);
  const Eigen::Vector3d n_new = m.cal.projector_in_flange.linear().col(0);
  out.plane_change_deg = std::acos(std::clamp(n_old.dot(n_new), -1.0, 1.0)) / kDeg;
  out.plane_change_mm = n_new.dot(m.cal.projector_in_flange.translation() -
                                  current.projector_in_flange.translation());
  out.spot_sightings = spots.size();
  out.stripe_views = stripes.size();
  out.stripe_points = points;
  out.iterations = ls.iterations;
  out.condition = ls.condition;
  return out;
}

}  // namespace ephor::stripe
