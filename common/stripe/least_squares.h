#pragma once
// The calibrations' nonlinear least squares, solved by Ceres
// (Levenberg-Marquardt, dense QR, central-difference Jacobians): tens of
// unknowns and a few thousand residuals computed by the arm's kinematics
// and the camera model, plain (non-templated) C++ where analytic or
// automatic derivatives would buy nothing but bugs. This is only the
// adapter from a residual function on Eigen vectors to one Ceres problem of
// one parameter block, plus the Jacobian's condition the calibrations
// report. Unknowns should be scaled to move the residuals comparably (e.g.
// mrad and mm).

#include <functional>
#include <string>

#include <Eigen/Core>

namespace ephor::stripe {

struct LeastSquaresOptions {
  int max_iterations = 100;
  // Ceres stops when the relative cost change, the relative step or the
  // gradient's max norm falls below these.
  double function_tolerance = 1e-12;
  double parameter_tolerance = 1e-12;
  double gradient_tolerance = 1e-12;
};

struct LeastSquaresResult {
  Eigen::VectorXd x;          // the minimiser
  Eigen::VectorXd residuals;  // at x
  double cost = 0.0;          // sum of squared residuals at x (not Ceres's half of it)
  int iterations = 0;         // Ceres's (successful and unsuccessful steps)
  bool converged = false;     // Ceres ended on one of the tolerances
  double condition = 0.0;     // of the Jacobian at x (largest / smallest singular value)
  std::string report;         // Ceres's one-line summary
};

// Minimises |f(x)|^2 from x0. f must return the same number of residuals
// for every x; a step to a non-finite cost is refused, and a non-finite
// cost at x0 ends the search with that cost.
LeastSquaresResult solve_least_squares(
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x0,
    const LeastSquaresOptions& options = {});

}  // namespace ephor::stripe
