#include "common/launch/process_usage.h"

#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "common/time/clock.h"

namespace ephor::deputy {
namespace {

TEST(ProcessUsage, ParsesStatWithAwkwardCommandNames) {
  // Fields after "(name)": state ppid pgrp session tty tpgid flags minflt
  // cminflt majflt cmajflt utime stime ...
  EXPECT_EQ(parse_stat_cpu_ticks("42 (a b) c)) S 1 42 42 0 -1 4194560 100 0 0 0 250 50 0 0 20"),
            300);
  EXPECT_FALSE(parse_stat_cpu_ticks("").has_value());
  EXPECT_FALSE(parse_stat_cpu_ticks("42 (x) S 1 2").has_value());
}

// The share of a CPU a spinning child really had, from the kernel's own
// per-process CPU clock, s.
double cpu_clock_s(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

TEST(ProcessUsage, MeasuresTheCpuShareABusyProcessHad) {
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    volatile uint64_t x = 0;
    while (true) x = x + 1;
  }
  clockid_t child_clock{};
  ASSERT_EQ(clock_getcpuclockid(child, &child_clock), 0);
  ProcessUsage usage;
  const int64_t start = mono_ns();
  const double cpu_start_s = cpu_clock_s(child_clock);
  ASSERT_TRUE(usage.sample(child, start).has_value());
  while (mono_ns() - start < 400'000'000) usleep(20'000);
  const int64_t end = mono_ns();
  const double cpu_end_s = cpu_clock_s(child_clock);
  const auto s = usage.sample(child, end);
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  ASSERT_TRUE(s.has_value());
  // What the child really had depends on the machine's load (a spinning
  // process had 5 % of a CPU on a loaded 2-core machine), so the sample is
  // checked against the kernel's clock of the same process: within the
  // 10 ms of /proc's ticks and the moments between the two readings.
  const double wall_s = static_cast<double>(end - start) * 1e-9;
  const double truth_percent = 100.0 * (cpu_end_s - cpu_start_s) / wall_s;
  EXPECT_NEAR(s->cpu_percent, truth_percent, 8.0);
  EXPECT_LT(s->cpu_percent, 110.0f);  // at most one CPU
  EXPECT_GT(s->rss_bytes, 0);
  EXPECT_FALSE(usage.sample(child, mono_ns()).has_value());  // gone
}

TEST(ProcessUsage, FindsTaggedProcessesWhoseDeputyIsGone) {
  const std::string tag = "test-" + std::to_string(getpid());
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    setenv("EPHOR_DEPUTY_TEST_TAG", tag.c_str(), 1);
    execl("/bin/sleep", "sleep", "30", static_cast<char*>(nullptr));
    _exit(127);
  }
  // Our child's parent is this test, not a deputy: it counts as left over.
  bool found = false;
  const int64_t start = mono_ns();
  while (!found && mono_ns() - start < 5'000'000'000) {
    for (pid_t p : find_leftovers("EPHOR_DEPUTY_TEST_TAG", tag, "ephor-deputy"))
      found = found || p == child;
    if (!found) usleep(10'000);  // until exec has replaced the environment
  }
  EXPECT_TRUE(found);
  // Under a live parent of that name it is not a leftover.
  EXPECT_TRUE(find_leftovers("EPHOR_DEPUTY_TEST_TAG", tag, process_comm(getpid())).empty());
  EXPECT_TRUE(find_leftovers("EPHOR_DEPUTY_TEST_TAG", tag + "x", "ephor-deputy").empty());
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
}

}  // namespace
}  // namespace ephor::deputy
