#include "common/stripe/least_squares.h"

#include <cmath>
#include <limits>

#include <ceres/ceres.h>
#include <Eigen/SVD>

namespace ephor::stripe {

namespace {

using ResidualFunction = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;

// f as Ceres's dynamic numeric-diff functor (one parameter block). A wrong
// residual count or a non-finite residual is an evaluation Ceres refuses
// (the step is rejected), without Ceres's logged warning for the latter.
class ResidualFunctor {
 public:
  ResidualFunctor(const ResidualFunction& f, Eigen::Index params, Eigen::Index residuals)
      : f_(f), params_(params), residuals_(residuals) {}

  bool operator()(double const* const* parameters, double* residuals) const {
    const Eigen::VectorXd r = f_(Eigen::Map<const Eigen::VectorXd>(parameters[0], params_));
    if (r.size() != residuals_ || !r.allFinite()) return false;
    Eigen::Map<Eigen::VectorXd>(residuals, residuals_) = r;
    return true;
  }

 private:
  const ResidualFunction& f_;
  Eigen::Index params_, residuals_;
};

// Largest over smallest singular value of the problem's Jacobian at its
// current parameters; infinite when it is singular or cannot be evaluated.
double jacobian_condition(ceres::Problem& problem) {
  ceres::CRSMatrix crs;
  if (!problem.Evaluate(ceres::Problem::EvaluateOptions(), nullptr, nullptr, nullptr, &crs))
    return std::numeric_limits<double>::infinity();
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row)
    for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) j(row, crs.cols[k]) = crs.values[k];
  const auto sv = Eigen::JacobiSVD<Eigen::MatrixXd>(j).singularValues();
  return sv.size() > 0 && sv[sv.size() - 1] > 0.0 ? sv[0] / sv[sv.size() - 1]
                                                  : std::numeric_limits<double>::infinity();
}

}  // namespace

LeastSquaresResult solve_least_squares(const ResidualFunction& f, const Eigen::VectorXd& x0,
                                       const LeastSquaresOptions& options) {
  LeastSquaresResult r;
  r.x = x0;
  r.residuals = f(r.x);
  r.cost = r.residuals.squaredNorm();
  if (!std::isfinite(r.cost) || r.x.size() == 0 || r.residuals.size() == 0) {
    r.condition = std::numeric_limits<double>::infinity();
    r.report = "not solved: no unknowns, no residuals or a non-finite cost at the start";
    return r;
  }
  const auto cost_function = new ceres::DynamicNumericDiffCostFunction<ResidualFunctor>(
      new ResidualFunctor(f, r.x.size(), r.residuals.size()));
  cost_function->AddParameterBlock(static_cast<int>(r.x.size()));
  cost_function->SetNumResiduals(static_cast<int>(r.residuals.size()));
  ceres::Problem problem;  // owns the cost function
  problem.AddResidualBlock(cost_function, nullptr, r.x.data());

  ceres::Solver::Options o;
  o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  o.linear_solver_type = ceres::DENSE_QR;
  o.max_num_iterations = options.max_iterations;
  o.function_tolerance = options.function_tolerance;
  o.parameter_tolerance = options.parameter_tolerance;
  o.gradient_tolerance = options.gradient_tolerance;
  o.num_threads = 1;  // one residual block: nothing to share out
  o.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(o, &problem, &summary);

  r.residuals = f(r.x);
  r.cost = r.residuals.squaredNorm();
  r.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
  r.converged = summary.termination_type == ceres::CONVERGENCE;
  r.condition = jacobian_condition(problem);
  r.report = summary.BriefReport();
  return r;
}

}  // namespace ephor::stripe
