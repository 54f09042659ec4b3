#include "common/sphere/sphere_fitter.h"

#include <cmath>

#include <Eigen/Dense>

namespace ephor::sphere {

SphereFit SphereFitter::fit(const std::vector<TimedPoint>& points) const {
  SphereFit out;
  const auto n = static_cast<Eigen::Index>(points.size());
  if (n < 6) return out;
  const double R = config_.sphere_radius_m;
  // Start: the points' centroid pushed back along the line of sight by 2R/3
  // (the mean depth of a hemisphere sampled uniformly over its silhouette).
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double t_ref = 0.0;
  for (const TimedPoint& q : points) {
    centroid += q.p_m;
    t_ref += q.t_s;
  }
  centroid /= static_cast<double>(n);
  t_ref /= static_cast<double>(n);
  out.t_ref_s = t_ref;
  Eigen::Matrix<double, 6, 1> x;
  x.head<3>() = centroid + centroid.normalized() * (2.0 * R / 3.0);
  x.tail<3>().setZero();

  const double sr2 = config_.range_sigma_m * config_.range_sigma_m;
  auto residuals = [&](const Eigen::Matrix<double, 6, 1>& params, Eigen::VectorXd& r,
                       Eigen::MatrixXd* J) {
    for (Eigen::Index i = 0; i < n; ++i) {
      const TimedPoint& q = points[static_cast<size_t>(i)];
      const double dt = q.t_s - t_ref;
      const Eigen::Vector3d c = params.head<3>() + params.tail<3>() * dt;
      const Eigen::Vector3d d = q.p_m - c;
      const double dist = d.norm();
      if (config_.residual == FitResidual::kRayRange) {
        const double range = q.p_m.norm();
        const Eigen::Vector3d u = q.p_m / range;
        const double b = u.dot(c);
        const double D = b * b - (c.squaredNorm() - R * R);
        const double sa = range * config_.angle_sigma_rad;
        if (D > 0.0) {
          const double sqrt_d = std::sqrt(D);
          const double r_hat = b - sqrt_d;
          // tan^2 of the incidence angle: (R^2 - D) / D.
          const double var = sr2 + sa * sa * (R * R - D) / D;
          const double inv_sigma = 1.0 / std::sqrt(var);
          r(i) = (range - r_hat) * inv_sigma;
          if (J) {
            // d r_hat / dc = u - (b u - c) / sqrt(D); residual derivative is its negative.
            const Eigen::Vector3d g = -(u - (b * u - c) / sqrt_d) * inv_sigma;
            J->row(i).head<3>() = g.transpose();
            J->row(i).tail<3>() = dt * g.transpose();
          }
        } else {
          const Eigen::Vector3d off = c - b * u;  // centre's offset from the ray
          const double miss = off.norm();
          r(i) = (miss - R) / sa;
          if (J) {
            const Eigen::Vector3d g =
                (miss > 1e-12 ? Eigen::Vector3d(off / miss) : Eigen::Vector3d::Zero()) / sa;
            J->row(i).head<3>() = g.transpose();
            J->row(i).tail<3>() = dt * g.transpose();
          }
        }
        continue;
      }
      if (config_.residual == FitResidual::kAlgebraic) {
        r(i) = d.squaredNorm() - R * R;  // eq. 6's term
        if (J) {
          J->row(i).head<3>() = -2.0 * d.transpose();
          J->row(i).tail<3>() = -2.0 * dt * d.transpose();
        }
        continue;
      }
      // Noise along the normal: range noise along the ray, encoder noise
      // (range x angle sigma, two axes) across it.
      const Eigen::Vector3d normal =
          dist > 1e-12 ? Eigen::Vector3d(d / dist) : Eigen::Vector3d::UnitZ();
      const double range = q.p_m.norm();
      const double cos_g = std::abs(normal.dot(q.p_m / range));
      const double sin2 = std::max(0.0, 1.0 - cos_g * cos_g);
      const double sa = range * config_.angle_sigma_rad;
      const double var_n = sr2 * cos_g * cos_g + sa * sa * sin2;
      const double var_perp = sr2 * sin2 + sa * sa * (1.0 + cos_g * cos_g);
      // Noise across the normal moves the point outward by n^2 / 2R: a
      // skewed error of variance ~ var_perp^2 / 2R^2 (3.5 mm at the limb for
      // sigma_r = 2 cm). Without it the limb points, precise along the
      // normal to first order, dominate the fit with a skewed error (a
      // 12 mm y bias at 1 m, where only the top half is scanned).
      const double inv_sigma = 1.0 / std::sqrt(var_n + var_perp * var_perp / (2.0 * R * R));
      const double offset = config_.noise_offset_correction ? var_perp / (2.0 * R) : 0.0;
      r(i) = (dist - R - offset) * inv_sigma;
      if (J) {
        J->row(i).head<3>() = -normal.transpose() * inv_sigma;
        J->row(i).tail<3>() = -dt * normal.transpose() * inv_sigma;
      }
    }
  };

  Eigen::VectorXd r(n), r_try(n);
  Eigen::MatrixXd J(n, 6);
  residuals(x, r, &J);
  double cost = r.squaredNorm();
  double mu = 1e-3;
  double last_step_m = INFINITY;
  for (int it = 0; it < config_.max_iterations; ++it) {
    out.iterations = it + 1;
    const Eigen::Matrix<double, 6, 6> H = J.transpose() * J;
    const Eigen::Matrix<double, 6, 1> g = J.transpose() * r;
    Eigen::Matrix<double, 6, 6> A = H;
    A.diagonal() += mu * H.diagonal().cwiseMax(1e-12);
    const Eigen::Matrix<double, 6, 1> step = -A.ldlt().solve(g);
    if (!step.allFinite()) break;
    const Eigen::Matrix<double, 6, 1> x_try = x + step;
    residuals(x_try, r_try, nullptr);
    const double cost_try = r_try.squaredNorm();
    if (cost_try <= cost) {
      x = x_try;
      residuals(x, r, &J);
      cost = r.squaredNorm();
      mu = std::max(mu * 0.2, 1e-9);
      last_step_m = step.head<3>().norm() + 0.25 * step.tail<3>().norm();
      // Position change in metres; velocity change over a 0.5 s window.
      if (step.head<3>().norm() + 0.25 * step.tail<3>().norm() < config_.step_tolerance_m) {
        out.converged = true;
        break;
      }
    } else {
      mu *= 10.0;
      if (mu > 1e8) {
        out.converged = true;  // no further descent possible: at the minimum
        break;
      }
    }
  }
  // Levenberg-Marquardt can crawl along a shallow valley (the velocity is
  // weakly observed with few lines): a last accepted step under 10 um is a
  // minimum for our purposes even when the iteration budget ran out.
  if (!out.converged && last_step_m < 1e-5) out.converged = true;
  out.centre_m = x.head<3>();
  out.velocity_m_s = x.tail<3>();
  if (!x.allFinite()) out.converged = false;
  return out;
}

Estimate SphereFitter::locate(const Window& window) const {
  ForegroundGate gate(config_.gate);
  if (gate.learn(window) == 0) {
    return Estimate::none("no returns closer than the background threshold");
  }
  std::vector<TimedPoint> points;
  int lines = 0;
  for (const ScanLine& line : window.lines) {
    bool any = false;
    for (const Pulse& p : line.pulses) {
      if (!gate.is_foreground(p)) continue;
      points.push_back({to_cartesian(p.azimuth_rad, p.elevation_rad, p.range_m), p.t_s});
      any = true;
    }
    lines += any ? 1 : 0;
  }
  const int n = static_cast<int>(points.size());
  if (n < std::max(6, config_.min_points)) {
    return Estimate::none("only " + std::to_string(n) + " points on the sphere (need " +
                              std::to_string(std::max(6, config_.min_points)) + ")",
                          n, lines);
  }
  const SphereFit f = fit(points);
  if (!f.converged) return Estimate::none("sphere fit did not converge", n, lines);
  Estimate e;
  e.ok = true;
  e.t_s = f.t_ref_s;
  e.position_m = f.centre_m;
  e.velocity_m_s = f.velocity_m_s;
  e.points = n;
  e.lines = lines;
  return e;
}

}  // namespace ephor::sphere
