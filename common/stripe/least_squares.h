#pragma once
// A small Levenberg-Marquardt solver on numerical Jacobians (central
// differences) for the calibrations here: tens of unknowns and a few
// thousand residuals, where writing analytic derivatives of the arm's
// kinematics and the camera would buy nothing but bugs. Unknowns should be
// scaled to move the residuals comparably (e.g. mrad and mm).

#include <functional>

#include <Eigen/Core>

namespace ephor::stripe {

struct LeastSquaresOptions {
  int max_iterations = 100;
  double step = 1e-4;  // central-difference step, in the unknowns' units
};

struct LeastSquaresResult {
  Eigen::VectorXd x;          // the minimiser
  Eigen::VectorXd residuals;  // at x
  double cost = 0.0;          // sum of squared residuals at x
  int iterations = 0;
  bool converged = false;  // relative cost change fell below 1e-12
  double condition = 0.0;  // of the Jacobian at x (largest / smallest singular value)
};

// Minimises |f(x)|^2 from x0. f must return the same number of residuals
// for every x (a non-finite cost ends the search).
LeastSquaresResult solve_least_squares(
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x0,
    const LeastSquaresOptions& options = {});

}  // namespace ephor::stripe
