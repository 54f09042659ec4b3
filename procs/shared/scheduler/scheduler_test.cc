#include "procs/shared/scheduler/scheduler.h"

#include <gtest/gtest.h>

namespace ephor::scheduler {
namespace {

TaskEntry periodic(const std::string& name, int64_t period_us, int cpu = -1) {
  TaskEntry e;
  e.process = "p";
  e.task = name;
  e.period_us = period_us;
  e.deadline_us = period_us;
  e.cpu = cpu;
  return e;
}

SchedReadback fake_readback(pid_t) {
  SchedReadback rb;
  rb.ok = true;
  rb.policy = Policy::kFifo;
  return rb;
}

JobsReport jobs(const std::string& task, int exec_us, int n, int32_t generation = 1,
                bool rt = true) {
  JobsReport r;
  r.process = "p";
  r.task = task;
  r.pid = 10;
  r.tid = 11;
  r.rt_granted = rt;
  r.rt_error = rt ? "" : "sched_setscheduler: Operation not permitted";
  r.generation = generation;
  for (int i = 0; i < n; ++i) r.jobs.push_back({5, exec_us, exec_us, true, 0});
  return r;
}

Registration reg(const std::string& task) {
  Registration r;
  r.process = "p";
  r.task = task;
  r.pid = 10;
  r.tid = 11;
  r.period_us = 10'000;
  return r;
}

SchedulerConfig two_cpus() {
  SchedulerConfig c;
  c.cpus = {0, 1};
  return c;
}

TEST(Scheduler, InitialAssignmentIsRateMonotonicAndFirstFit) {
  Scheduler s(two_cpus(),
              {periodic("slow", 100'000), periodic("fast", 1'000), periodic("pinned", 10'000, 1)});
  const auto a = s.assignments();
  ASSERT_EQ(a.size(), 3u);
  EXPECT_EQ(a[1].priority, 80);  // fastest
  EXPECT_EQ(a[2].priority, 79);
  EXPECT_EQ(a[0].priority, 78);
  EXPECT_EQ(a[2].cpu, 1);
  EXPECT_EQ(a[0].policy, Policy::kFifo);
}

TEST(Scheduler, MigratesWhenMeasuredUtilisationPassesTheBound) {
  // With no estimates both auto tasks start on CPU 0.
  Scheduler s(two_cpus(), {periodic("a", 10'000), periodic("b", 10'000)});
  ASSERT_EQ(s.assignments()[0].cpu, 0);
  ASSERT_EQ(s.assignments()[1].cpu, 0);
  s.on_register(reg("a"), 1'000'000);
  s.on_register(reg("b"), 1'000'000);
  // 6 ms of 10 ms each: 1.2 > 0.83 on CPU 0.
  s.on_jobs(jobs("a", 6000, 10), 1'100'000);
  s.on_jobs(jobs("b", 6000, 10), 1'100'000);
  const auto events = s.rebalance(2'000'000);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_NE(events[0].find("migrating p/a from CPU 0 to CPU 1"), std::string::npos) << events[0];
  const auto a = s.assignments();
  EXPECT_EQ(a[0].cpu, 1);
  EXPECT_EQ(a[0].generation, 2);  // the runtime sees a new generation: the migrate flag
  EXPECT_EQ(a[1].cpu, 0);
  // Once balanced, nothing more moves.
  EXPECT_TRUE(s.rebalance(9'000'000).empty());
}

TEST(Scheduler, PinnedTasksAreNeverMigrated) {
  Scheduler s(two_cpus(), {periodic("a", 10'000, 0), periodic("b", 10'000, 0)});
  s.on_register(reg("a"), 0);
  s.on_register(reg("b"), 0);
  s.on_jobs(jobs("a", 6000, 3), 0);
  s.on_jobs(jobs("b", 6000, 3), 0);
  EXPECT_TRUE(s.rebalance(1'000'000).empty());
}

TEST(Scheduler, UtilisationEstimateIsMaxOfNewestThreeJobs) {
  Scheduler s(two_cpus(), {periodic("a", 10'000)}, fake_readback);
  s.on_register(reg("a"), 0);
  JobsReport r = jobs("a", 0, 0);
  for (int exec : {9000, 1000, 2000, 3000}) r.jobs.push_back({0, exec, exec, true, 0});
  s.on_jobs(r, 0);
  const auto st = s.status(0);
  EXPECT_NEAR(st.tasks[0].utilisation, 0.3, 1e-9);  // 3000 us of 10 ms, not 9000
  EXPECT_EQ(st.tasks[0].exec_max, 9000);
  EXPECT_EQ(st.tasks[0].jobs, 4);
}

TEST(Scheduler, RefusedFifoIsReportedOnceAndClearsRt) {
  Scheduler s(two_cpus(), {periodic("a", 10'000)}, fake_readback);
  s.on_register(reg("a"), 0);
  s.on_jobs(jobs("a", 100, 5, 1, /*rt=*/false), 0);
  s.on_jobs(jobs("a", 100, 5, 1, /*rt=*/false), 0);
  const auto refusals = s.take_new_refusals();
  ASSERT_EQ(refusals.size(), 1u);
  EXPECT_NE(refusals[0].find("Operation not permitted"), std::string::npos);
  EXPECT_TRUE(s.take_new_refusals().empty());
  const auto st = s.status(0);
  EXPECT_FALSE(st.rt);
  EXPECT_FALSE(st.tasks[0].rt_granted);
}

TEST(Scheduler, UnknownTaskRunsUnderSchedOther) {
  Scheduler s(two_cpus(), {});
  s.on_register(reg("stray"), 0);
  const auto a = s.assignments();
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0].policy, Policy::kOther);
  EXPECT_EQ(a[0].cpu, -1);
  EXPECT_NE(s.events().back().find("not in the task table"), std::string::npos);
}

TEST(Scheduler, DeadlineMissesCountLateJobsAndSkippedReleases) {
  Scheduler s(two_cpus(), {periodic("a", 10'000)}, fake_readback);
  s.on_register(reg("a"), 0);
  JobsReport r = jobs("a", 0, 0);
  r.jobs.push_back({0, 100, 100, true, 0});
  r.jobs.push_back({0, 15000, 15000, false, 0});
  r.jobs.push_back({0, 100, 100, true, 2});
  s.on_jobs(r, 0);
  EXPECT_EQ(s.status(0).tasks[0].deadline_misses, 3);
}

}  // namespace
}  // namespace ephor::scheduler
