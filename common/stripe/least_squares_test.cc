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

// Two unknowns only their sum is seen in: the solver still ends (the
// damping keeps the step finite) and says the problem is singular.
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

}  // namespace
}  // namespace ephor::stripe
