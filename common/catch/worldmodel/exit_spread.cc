#include "common/catch/worldmodel/exit_spread.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include <Eigen/Eigenvalues>

namespace ephor::catching {

ExitSpread::ExitSpread(const ExitPredictor& predictor, const ExitSpreadParams& params)
    : predictor_(predictor), params_(params) {
  if (params_.samples < 1) throw std::invalid_argument("ExitSpread: samples must be >= 1");
  if (!(params_.peg_sigma_mm >= 0.0) || !std::isfinite(params_.peg_sigma_mm))
    throw std::invalid_argument("ExitSpread: peg_sigma_mm must be finite and >= 0");
  if (!(params_.capture_radius_mm > 0.0) || !std::isfinite(params_.capture_radius_mm))
    throw std::invalid_argument("ExitSpread: capture_radius_mm must be finite and > 0");
}

namespace {

// The covered samples of centre c (horizontal distance in W within r): count
// and the sum of their distances (the tie-break).
struct Coverage {
  int count = 0;
  double distance_sum = 0.0;
  bool better_than(const Coverage& o) const {
    return count > o.count || (count == o.count && distance_sum < o.distance_sum);
  }
};
Coverage coverage(const std::vector<ExitSample>& exits, const Eigen::Vector2d& c, double r) {
  Coverage cov;
  for (const ExitSample& e : exits) {
    const double d = (e.catch_point_w_mm.head<2>() - c).norm();
    if (d <= r) {
      ++cov.count;
      cov.distance_sum += d;
    }
  }
  return cov;
}

}  // namespace

ExitSpreadResult ExitSpread::sample(const Eigen::Vector4d& state,
                                    const Eigen::Matrix4d& covariance) const {
  ExitSpreadResult out;
  out.samples = params_.samples;
  if (!state.allFinite() || !covariance.allFinite()) return out;

  // A square root of the covariance, its negative eigenvalues (rounding)
  // clipped: state = mean + root * z, z ~ N(0, I).
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(0.5 *
                                                             (covariance + covariance.transpose()));
  const Eigen::Matrix4d root =
      eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();

  std::mt19937_64 rng(params_.seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  ExitPredictor predictor = predictor_;  // its pegs are moved per sample
  const std::vector<Eigen::Vector2d>& pegs = predictor_.pegs();
  std::vector<Eigen::Vector2d> moved = pegs;
  out.exits.reserve(static_cast<size_t>(params_.samples));
  for (int i = 0; i < params_.samples; ++i) {
    Eigen::Vector4d s = state;
    if (i > 0) {
      Eigen::Vector4d z;
      for (int k = 0; k < 4; ++k) z(k) = unit(rng);
      s += root * z;
      if (!pegs.empty()) {
        for (size_t j = 0; j < pegs.size(); ++j) {
          const double dx = unit(rng), dy = unit(rng);
          moved[j] = pegs[j] + params_.peg_sigma_mm * Eigen::Vector2d(dx, dy);
        }
        predictor.set_pegs(moved, predictor_.peg_radius_mm(), predictor_.restitution());
      }
    }
    const ExitPrediction e = predictor.predict(s, Eigen::Matrix4d::Zero());
    if (!e.ok() || e.stalled_on_pegs || !e.catch_point_w_mm.allFinite()) continue;
    out.exits.push_back({e.exit_x_b_mm, e.time_to_catch_s, e.catch_point_w_mm, e.peg_bounces});
  }
  if (out.exits.empty()) return out;
  out.ok = true;

  // The cover: the best of the samples' own points, then the mean of what it
  // covers if that covers no fewer.
  const double r = params_.capture_radius_mm;
  Eigen::Vector2d best_c = out.exits.front().catch_point_w_mm.head<2>();
  Coverage best = coverage(out.exits, best_c, r);
  for (const ExitSample& e : out.exits) {
    const Eigen::Vector2d c = e.catch_point_w_mm.head<2>();
    const Coverage cov = coverage(out.exits, c, r);
    if (cov.better_than(best)) {
      best = cov;
      best_c = c;
    }
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const ExitSample& e : out.exits)
    if ((e.catch_point_w_mm.head<2>() - best_c).norm() <= r) mean += e.catch_point_w_mm.head<2>();
  mean /= best.count;
  if (const Coverage at_mean = coverage(out.exits, mean, r); at_mean.count >= best.count) {
    best = at_mean;
    best_c = mean;
  }
  double exit_x = 0.0, time = 0.0, z = 0.0;
  for (const ExitSample& e : out.exits) {
    if ((e.catch_point_w_mm.head<2>() - best_c).norm() > r) continue;
    exit_x += e.exit_x_b_mm;
    time += e.time_to_catch_s;
    z += e.catch_point_w_mm.z();
  }
  out.cover_point_w_mm = Eigen::Vector3d(best_c.x(), best_c.y(), z / best.count);
  out.cover_exit_x_b_mm = exit_x / best.count;
  out.cover_time_to_catch_s = time / best.count;
  out.cover_fraction = static_cast<double>(best.count) / params_.samples;

  std::vector<double> xs;
  xs.reserve(out.exits.size());
  double sum = 0.0, sum2 = 0.0;
  for (const ExitSample& e : out.exits) {
    xs.push_back(e.exit_x_b_mm);
    sum += e.exit_x_b_mm;
    sum2 += e.exit_x_b_mm * e.exit_x_b_mm;
  }
  std::sort(xs.begin(), xs.end());
  const auto at = [&xs](double q) {
    return xs[std::min(xs.size() - 1, static_cast<size_t>(q * static_cast<double>(xs.size())))];
  };
  out.exit_x_p10_mm = at(0.1);
  out.exit_x_p90_mm = at(0.9);
  const double n = static_cast<double>(xs.size());
  out.exit_x_sd_mm = std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
  return out;
}

}  // namespace ephor::catching
