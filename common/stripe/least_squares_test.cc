#include "common/stripe/least_squares.h"

#include <cmath>

#include <gtest/gtest.h>

namespace ephor::stripe {
namespace {

// y = a exp(b x) through exact samples: the minimiser is (a, b), from a
// start well off it.
TEST(LeastSquaresTest, FitsAnExponentialExactly) {
  const double a = 2.5, b = -0.7;
  Eigen::VectorXd xs = Eigen::VectorXd::LinSpaced(20, 0.0, 4.0);
  auto f = [&](const Eigen::VectorXd& p) {
    Eigen::VectorXd r(xs.size());
    for (Eigen::Index i = 0; i < xs.size(); ++i)
      r[i] = p[0] * std::exp(p[1] * xs[i]) - a * std::exp(b * xs[i]);
    return r;
  };
  const LeastSquaresResult r = solve_least_squares(f, Eigen::Vector2d(1.0, 0.3));
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.x[0], a, 1e-6);
  EXPECT_NEAR(r.x[1], b, 1e-6);
  EXPECT_LT(r.cost, 1e-12);
  EXPECT_GT(r.condition, 1.0);
  EXPECT_TRUE(std::isfinite(r.condition));
}

// Two unknowns only their sum is seen in: the solver still ends
// (Levenberg-Marquardt's damping keeps the step finite) and says the
// problem is singular.
TEST(LeastSquaresTest, RedundantUnknownsAreReportedByTheCondition) {
  auto f = [](const Eigen::VectorXd& p) {
    Eigen::VectorXd r(3);
    r << p[0] + p[1] - 1.0, 2.0 * (p[0] + p[1]) - 2.0, p[2] - 3.0;
    return r;
  };
  const LeastSquaresResult r = solve_least_squares(f, Eigen::Vector3d::Zero());
  EXPECT_NEAR(r.x[0] + r.x[1], 1.0, 1e-6);
  EXPECT_NEAR(r.x[2], 3.0, 1e-6);
  EXPECT_GT(r.condition, 1e6);
}

// The calibrations' "fit diverged" check: a non-finite cost at the start
// comes back as it is, with x0.
TEST(LeastSquaresTest, ANonFiniteStartIsReturnedAsIs) {
  auto f = [](const Eigen::VectorXd& p) {
    Eigen::VectorXd r(2);
    r << std::log(p[0]), p[0] - 1.0;
    return r;
  };
  const LeastSquaresResult r = solve_least_squares(f, Eigen::VectorXd::Constant(1, -1.0));
  EXPECT_FALSE(std::isfinite(r.cost));
  EXPECT_EQ(r.x[0], -1.0);
  EXPECT_FALSE(r.converged);
}

// Steps into the region where f is not finite (x < 0) are refused, not taken.
TEST(LeastSquaresTest, StepsToANonFiniteCostAreRefused) {
  auto f = [](const Eigen::VectorXd& p) {
    Eigen::VectorXd r(1);
    r << std::sqrt(p[0]) - 0.1;
    return r;
  };
  const LeastSquaresResult r = solve_least_squares(f, Eigen::VectorXd::Constant(1, 4.0));
  EXPECT_NEAR(r.x[0], 0.01, 1e-8);
  EXPECT_LT(r.cost, 1e-16);
}

}  // namespace
}  // namespace ephor::stripe
