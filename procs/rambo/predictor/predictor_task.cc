#include "procs/rambo/predictor/predictor_task.h"

#include <cmath>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "common/rambo/prediction_message.h"

namespace ephor::rambo {

namespace {

template <std::size_t N>
bool all_finite(const double (&v)[N]) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

// Every number a fitted prediction carries, its uncertainties non-negative.
bool prediction_finite(const rambo_prediction_t& p) {
  return all_finite(p.position_mm) && all_finite(p.velocity_mm_s) &&
         all_finite(p.orientation_wxyz) && all_finite(p.body_rates_rad_s) &&
         all_finite(p.principal_moments) && all_finite(p.poly_r_mid_wxyz) &&
         all_finite(p.poly_coeff) && std::isfinite(p.poly_t_mid_s) &&
         std::isfinite(p.poly_t_scale_s) && std::isfinite(p.rms_rotation_residual_rad) &&
         std::isfinite(p.position_sigma_mm) && p.position_sigma_mm >= 0.0 &&
         std::isfinite(p.rotation_sigma_rad) && p.rotation_sigma_rad >= 0.0;
}

}  // namespace

PoseFitter::PoseFitter(const PoseFitterOptions& options)
    : options_(options),
      rigid_(options.principal_moments),
      poly_(options.poly_degree, options.poly_rotation),
      predictor_(options.polynomial ? static_cast<PosePredictor*>(&poly_) : &rigid_) {}

std::optional<rambo_prediction_t> PoseFitter::on_pose(const rambo_pose_t& m, int64_t now_us) {
  if (!m.found) return std::nullopt;
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) p.linear()(i, j) = m.target_r[3 * i + j];
    p.translation()[i] = m.target_t_mm[i];
  }
  const bool orthonormal =
      (p.linear().transpose() * p.linear() - Eigen::Matrix3d::Identity()).norm() < 1e-6;
  if (!p.matrix().allFinite() || !orthonormal || !(m.rms_reprojection_px <= options_.max_rms_px) ||
      !(p.translation().norm() <= kMaxDistanceMm) ||
      (!window_.empty() && m.utime <= window_.back().first)) {
    ++dropped_;
    return std::nullopt;
  }
  if (!window_.empty() &&
      static_cast<double>(m.utime) - static_cast<double>(window_.back().first) > kMaxGapS * 1e6) {
    spdlog::warn("a pose {:.0f} s after the last: fitting afresh",
                 (static_cast<double>(m.utime) - static_cast<double>(window_.back().first)) * 1e-6);
    window_.clear();
    fit_valid_ = false;
    outliers_in_row_ = 0;
    epoch_utime_ = -1;
  }
  if (epoch_utime_ < 0) epoch_utime_ = m.utime;
  // A pose far from the fitted motion is a wrong cluster (a near-symmetric
  // view): dropped, unless refit_after in a row disagree (then the fit is
  // the one that is wrong and starts again).
  if (fit_valid_ && !window_.empty()) {
    const PosePrediction expected =
        predictor_->predict(static_cast<double>(m.utime - epoch_utime_) * 1e-6);
    const bool outlier =
        (expected.pose.translation() - p.translation()).norm() > options_.max_jump_mm ||
        rotation_angle_between(expected.pose.linear(), p.linear()) >
            options_.max_jump_deg * M_PI / 180.0;
    if (outlier && ++outliers_in_row_ < options_.refit_after) {
      ++dropped_;
      return std::nullopt;
    }
    if (outlier) {
      spdlog::warn("{} poses in a row off the fitted motion: fitting afresh", options_.refit_after);
      window_.clear();
      fit_valid_ = false;
    }
    outliers_in_row_ = 0;
  }
  window_.emplace_back(m.utime, p);
  while (!window_.empty() &&
         static_cast<double>(m.utime - window_.front().first) * 1e-6 > options_.window_s)
    window_.pop_front();
  rambo_prediction_t out{};
  no_polynomial(&out);
  out.utime = now_us;
  out.model = predictor_->name();
  out.ref_utime = m.utime;
  out.samples = static_cast<int32_t>(window_.size());
  if (static_cast<int>(window_.size()) < options_.min_samples) {
    out.reason = "waiting for " + std::to_string(options_.min_samples) + " poses";
    return out;
  }
  std::vector<PoseSample> samples;
  for (const auto& [u, pose] : window_)
    samples.push_back({static_cast<double>(u - epoch_utime_) * 1e-6, pose});
  std::string why;
  if (!predictor_->fit(samples, &why)) {
    ++failures_;
    fit_valid_ = false;
    out.reason = why;
    return out;
  }
  const double t_ref = samples.back().t_s;
  const PosePrediction now = predictor_->predict(t_ref);
  const Eigen::Vector3d v =
      predictor_->predict(t_ref + 1.0).pose.translation() - now.pose.translation();
  const Eigen::Quaterniond q(now.pose.linear());
  // The polynomial's body rates at t_ref (for the page and a reader that
  // takes the rigid-body fields): R^T R' by a central difference of 10 ms.
  Eigen::Vector3d w = Eigen::Vector3d::Zero();
  if (options_.polynomial) {
    const Eigen::AngleAxisd d(predictor_->predict(t_ref - 0.005).pose.linear().transpose() *
                              predictor_->predict(t_ref + 0.005).pose.linear());
    w = d.axis() * d.angle() / 0.01;
    polynomial_to_message(poly_.motion(), t_ref, &out);
  } else {
    w = rigid_.body_rates_rad_s();
    no_polynomial(&out);
  }
  out.fitted = true;
  for (int k = 0; k < 3; ++k) {
    out.position_mm[k] = now.pose.translation()[k];
    out.velocity_mm_s[k] = v[k];
    out.body_rates_rad_s[k] = w[k];
    out.principal_moments[k] = options_.principal_moments[k];
  }
  out.orientation_wxyz[0] = q.w();
  out.orientation_wxyz[1] = q.x();
  out.orientation_wxyz[2] = q.y();
  out.orientation_wxyz[3] = q.z();
  out.position_sigma_mm = now.position_sigma_mm;
  out.rotation_sigma_rad = now.rotation_sigma_rad;
  out.rms_rotation_residual_rad = options_.polynomial ? 0.0 : rigid_.rms_rotation_residual_rad();
  if (!prediction_finite(out)) {
    ++failures_;
    fit_valid_ = false;
    rambo_prediction_t refused{};
    no_polynomial(&refused);
    refused.utime = out.utime;
    refused.model = out.model;
    refused.ref_utime = out.ref_utime;
    refused.samples = out.samples;
    refused.reason = "the fit's prediction is not finite";
    return refused;
  }
  ++fits_;
  fit_valid_ = true;
  return out;
}

}  // namespace ephor::rambo
