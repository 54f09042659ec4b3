#include "procs/shared/scheduler/partitioner.h"

#include <cmath>

#include <gtest/gtest.h>

#include "common/config/manifest.h"
#include "procs/shared/scheduler/task_table.h"

namespace ephor::scheduler {
namespace {

TEST(LiuLayland, KnownValues) {
  EXPECT_DOUBLE_EQ(liu_layland_bound(1), 1.0);
  EXPECT_NEAR(liu_layland_bound(2), 0.8284, 1e-4);
  EXPECT_NEAR(liu_layland_bound(3), 0.7798, 1e-4);
  EXPECT_NEAR(liu_layland_bound(1000), std::log(2.0), 1e-3);
}

TEST(FirstFitDecreasing, PlacesLargestFirstIntoFirstFit) {
  // 0.6 -> CPU 0; 0.5 does not fit with 0.6 (bound 0.83) -> CPU 1;
  // 0.2 fits on CPU 0 (0.8 <= 0.83); 0.1 does not fit on CPU 0 (0.9 > 0.78) -> CPU 1.
  const std::vector<PartitionItem> items = {{0.1, -1}, {0.5, -1}, {0.6, -1}, {0.2, -1}};
  const Partition p = first_fit_decreasing(items, {0, 1}, 0.0);
  EXPECT_EQ(p.cpu_of, (std::vector<int>{1, 1, 0, 0}));
  EXPECT_NEAR(p.cpu_utilisation[0], 0.8, 1e-12);
  EXPECT_NEAR(p.cpu_utilisation[1], 0.6, 1e-12);
  EXPECT_TRUE(p.feasible);
}

TEST(FirstFitDecreasing, PinnedTasksStayAndCount) {
  const std::vector<PartitionItem> items = {{0.7, 1}, {0.3, -1}};
  const Partition p = first_fit_decreasing(items, {0, 1}, 0.0);
  EXPECT_EQ(p.cpu_of[0], 1);
  EXPECT_EQ(p.cpu_of[1], 0);
}

TEST(FirstFitDecreasing, OverloadIsReportedInfeasible) {
  const std::vector<PartitionItem> items = {{0.9, -1}, {0.9, -1}, {0.9, -1}};
  const Partition p = first_fit_decreasing(items, {0, 1}, 0.0);
  EXPECT_FALSE(p.feasible);
}

TEST(FirstFitDecreasing, UsesOnlyAllowedCpuNumbers) {
  const Partition p = first_fit_decreasing({{0.5, -1}, {0.5, -1}}, {3, 5}, 0.6);
  EXPECT_EQ(p.cpu_of, (std::vector<int>{3, 5}));
}

TEST(PlanMigration, NothingToDoWithinBound) {
  EXPECT_FALSE(plan_migration({0.3, 0.3}, {0, 0}, {true, true}, {0, 1}, 0.0).has_value());
}

TEST(PlanMigration, MovesLargestMovableTaskThatFits) {
  // CPU 0: 0.5 + 0.4 = 0.9 > 0.83; the 0.5 task is pinned, so the 0.4 moves.
  const auto m = plan_migration({0.5, 0.4, 0.1}, {0, 0, 1}, {false, true, true}, {0, 1}, 0.0);
  ASSERT_TRUE(m.has_value());
  EXPECT_EQ(m->item, 1u);
  EXPECT_EQ(m->from_cpu, 0);
  EXPECT_EQ(m->to_cpu, 1);
  EXPECT_NE(m->reason.find("CPU 0 utilisation 0.90 > bound 0.83"), std::string::npos) << m->reason;
}

TEST(PlanMigration, NoMoveWhenNothingFitsElsewhere) {
  EXPECT_FALSE(
      plan_migration({0.6, 0.6, 0.7}, {0, 0, 1}, {true, true, true}, {0, 1}, 0.0).has_value());
}

TEST(TaskTable, RateMonotonicPrioritiesFromManifest) {
  const auto m = parse_manifest(R"pb(
                                  name: "t"
                                  process {
                                    name: "a"
                                    exec: "x"
                                    task { name: "fast" kind: PERIODIC period_ms: 1 }
                                    task { name: "slow" kind: PERIODIC period_ms: 100 }
                                    task { name: "fixed" kind: PERIODIC period_ms: 50 priority: 10 }
                                    task { name: "other" kind: PERIODIC period_ms: 5 policy: OTHER }
                                    task { name: "trig" kind: TRIGGERED deadline_ms: 20 cpu: "1" }
                                  })pb",
                                "t");
  auto table = build_task_table(m, "");
  assign_rate_monotonic(table, 80);
  ASSERT_EQ(table.size(), 5u);
  EXPECT_EQ(table[0].priority, 80);  // 1 ms
  EXPECT_EQ(table[4].priority, 79);  // 20 ms deadline
  EXPECT_EQ(table[1].priority, 78);  // 100 ms
  EXPECT_EQ(table[2].priority, 10);  // explicit
  EXPECT_EQ(table[3].priority, 0);   // SCHED_OTHER
  EXPECT_EQ(table[4].cpu, 1);
  EXPECT_FALSE(table[4].periodic);
}

}  // namespace
}  // namespace ephor::scheduler
