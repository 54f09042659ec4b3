#include "common/stripe/least_squares.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>
#include <Eigen/SVD>

namespace ephor::stripe {

namespace {

Eigen::MatrixXd jacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                         const Eigen::VectorXd& x, Eigen::Index rows, double h) {
  Eigen::MatrixXd j(rows, x.size());
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    Eigen::VectorXd a = x, b = x;
    a[k] += h;
    b[k] -= h;
    j.col(k) = (f(a) - f(b)) / (2.0 * h);
  }
  return j;
}

}  // namespace

LeastSquaresResult solve_least_squares(
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x0,
    const LeastSquaresOptions& options) {
  LeastSquaresResult r;
  r.x = x0;
  r.residuals = f(r.x);
  r.cost = r.residuals.squaredNorm();
  double lambda = 1e-3;
  for (; r.iterations < options.max_iterations && !r.converged && std::isfinite(r.cost);
       ++r.iterations) {
    const Eigen::MatrixXd j = jacobian(f, r.x, r.residuals.size(), options.step);
    const Eigen::MatrixXd a = j.transpose() * j;
    const Eigen::VectorXd g = j.transpose() * r.residuals;
    bool improved = false;
    Eigen::VectorXd step;
    while (lambda < 1e12) {
      // Marquardt's scaling: damp each unknown by its own curvature.
      Eigen::MatrixXd damped = a;
      damped.diagonal() += lambda * a.diagonal().cwiseMax(1e-9);
      step = damped.ldlt().solve(-g);
      const Eigen::VectorXd trial = r.x + step;
      const Eigen::VectorXd res = f(trial);
      const double cost = res.squaredNorm();
      if (cost < r.cost) {
        r.converged = r.cost - cost < 1e-12 * std::max(1.0, cost);
        r.x = trial;
        r.residuals = res;
        r.cost = cost;
        lambda = std::max(1e-12, lambda / 10.0);
        improved = true;
        break;
      }
      lambda *= 10.0;
    }
    if (!improved || step.norm() < 1e-9) {
      r.converged = true;
      break;
    }
  }
  const Eigen::MatrixXd j = jacobian(f, r.x, r.residuals.size(), options.step);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(j);
  const auto sv = svd.singularValues();
  r.condition = sv.size() > 0 && sv[sv.size() - 1] > 0.0 ? sv[0] / sv[sv.size() - 1]
                                                         : std::numeric_limits<double>::infinity();
  return r;
}

}  // namespace ephor::stripe
