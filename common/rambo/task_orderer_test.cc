#include "common/rambo/task_orderer.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Core>

namespace ephor::rambo {
namespace {

// Goal points circling in the work space (mm, s); the tool moves between
// them at 500 mm/s plus a 0.3 s settle. Goal speeds are at most ~100 mm/s,
// so the reaching duration changes slower than time (|dT/dt| <= 0.4) and
// arrival is monotone in launch time: DP is exact here (see the header).
struct CirclingGoals {
  std::vector<Eigen::Vector3d> centre_mm;
  std::vector<double> radius_mm, omega_rad_s, phase_rad;
  Eigen::Vector3d tool_start_mm{0, 0, 0};

  explicit CirclingGoals(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(-400.0, 400.0), r(20.0, 150.0), w(0.1, 0.6),
        ph(0.0, 6.28);
    for (int i = 0; i < n; ++i) {
      centre_mm.emplace_back(pos(rng), pos(rng), pos(rng));
      radius_mm.push_back(r(rng));
      omega_rad_s.push_back(std::min(w(rng), 80.0 / radius_mm.back()));  // <= 80 mm/s
      phase_rad.push_back(ph(rng));
    }
    tool_start_mm = Eigen::Vector3d(pos(rng), pos(rng), pos(rng));
  }
  Eigen::Vector3d goal(int i, double t) const {
    const auto k = static_cast<std::size_t>(i);
    const double a = omega_rad_s[k] * t + phase_rad[k];
    return centre_mm[k] + radius_mm[k] * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
  }
  double duration(int from, int to, double t) const {
    const Eigen::Vector3d p = from < 0 ? tool_start_mm : goal(from, t);
    return 0.3 + (goal(to, t) - p).norm() / 500.0;
  }
};

TEST(TaskOrderer, PaperFiguresForFourTasks) {
  EXPECT_EQ(TaskOrderer::paper_exhaustive_count(4), 64);
  EXPECT_EQ(TaskOrderer::exhaustive_count(4), 64);
  EXPECT_EQ(TaskOrderer::paper_dp_count(4), 32);  // DP states, one kept trajectory each
  EXPECT_EQ(TaskOrderer::dp_count(4), 52);        // trajectories DP actually computes
  EXPECT_EQ(TaskOrderer::greedy_count(4), 10);
  for (int n = 1; n <= 10; ++n) {
    EXPECT_EQ(TaskOrderer::paper_exhaustive_count(n), TaskOrderer::exhaustive_count(n)) << n;
    EXPECT_EQ(TaskOrderer::paper_dp_count(n), std::int64_t{n} << (n - 1)) << n;
  }
}

TEST(TaskOrderer, CountsMatchFormulasForTwoToEightTasks) {
  for (int n = 2; n <= 8; ++n) {
    CirclingGoals g(n, 100u + static_cast<unsigned>(n));
    TaskOrderer o(std::vector<double>(static_cast<std::size_t>(n), 0.5),
                  [&g](int f, int t, double s) { return g.duration(f, t, s); });
    EXPECT_EQ(o.greedy(0.0).reaching_trajectories, TaskOrderer::greedy_count(n)) << n;
    EXPECT_EQ(o.exhaustive(0.0).reaching_trajectories, TaskOrderer::exhaustive_count(n)) << n;
    EXPECT_EQ(o.dynamic_programming(0.0).reaching_trajectories, TaskOrderer::dp_count(n)) << n;
  }
}

TEST(TaskOrderer, DpOrderEqualsExhaustiveOnRandomCases) {
  int dp_beats_greedy = 0;
  for (unsigned seed = 1; seed <= 40; ++seed) {
    const int n = 2 + static_cast<int>(seed % 6);  // 2..7 tasks
    CirclingGoals g(n, seed);
    std::vector<double> hold;
    for (int i = 0; i < n; ++i) hold.push_back(0.2 + 0.1 * i);
    TaskOrderer o(hold, [&g](int f, int t, double s) { return g.duration(f, t, s); });
    const TaskOrder ex = o.exhaustive(1.0);
    const TaskOrder dp = o.dynamic_programming(1.0);
    const TaskOrder gr = o.greedy(1.0);
    ASSERT_TRUE(ex.feasible && dp.feasible && gr.feasible);
    EXPECT_EQ(dp.order, ex.order) << "seed " << seed;
    EXPECT_NEAR(dp.total_time_s, ex.total_time_s, 1e-9) << "seed " << seed;
    EXPECT_NEAR(dp.moving_time_s, ex.moving_time_s, 1e-9) << "seed " << seed;
    EXPECT_GE(gr.total_time_s, ex.total_time_s - 1e-9);
    // The kept DP times are those of re-evaluating its order from scratch.
    const TaskOrder re = o.evaluate(dp.order, 1.0);
    EXPECT_NEAR(re.total_time_s, dp.total_time_s, 1e-9);
    ASSERT_EQ(re.done_s.size(), dp.done_s.size());
    for (std::size_t i = 0; i < re.done_s.size(); ++i)
      EXPECT_NEAR(re.done_s[i], dp.done_s[i], 1e-9);
    if (gr.total_time_s > ex.total_time_s + 1e-6) ++dp_beats_greedy;
  }
  EXPECT_GT(dp_beats_greedy, 0);  // greedy is not optimal on some of these
}

TEST(TaskOrderer, UnreachableTaskMakesOrderInfeasible) {
  TaskOrderer o({0.1, 0.1}, [](int, int to, double) {
    return to == 1 ? std::numeric_limits<double>::infinity() : 1.0;
  });
  EXPECT_FALSE(o.greedy(0).feasible);
  EXPECT_FALSE(o.exhaustive(0).feasible);
  EXPECT_FALSE(o.dynamic_programming(0).feasible);
}

TEST(TaskOrderer, BadInputIsRejected) {
  const auto one = [](int, int, double) { return 1.0; };
  EXPECT_THROW(TaskOrderer({-1.0}, one), std::invalid_argument);
  EXPECT_THROW(TaskOrderer({std::nan("")}, one), std::invalid_argument);
  EXPECT_THROW(TaskOrderer({1.0}, ReachingDurationFn{}), std::invalid_argument);
  // A NaN duration from the callback is "unreachable", not a crash.
  TaskOrderer o({0.0}, [](int, int, double) { return std::nan(""); });
  EXPECT_FALSE(o.dynamic_programming(0).feasible);
}

}  // namespace
}  // namespace ephor::rambo
