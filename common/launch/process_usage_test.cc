#include "common/launch/process_usage.h"

#include <signal.h>
#include <sys/wait.h>
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

TEST(ProcessUsage, MeasuresABusyProcessNearOneCpu) {
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    volatile uint64_t x = 0;
    while (true) x = x + 1;
  }
  ProcessUsage usage;
  ASSERT_TRUE(usage.sample(child, mono_ns()).has_value());
  const int64_t start = mono_ns();
  while (mono_ns() - start < 400'000'000) usleep(20'000);
  const auto s = usage.sample(child, mono_ns());
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  ASSERT_TRUE(s.has_value());
  // A spinning process on a shared 2-core machine: well above idle, at most 1 CPU.
  EXPECT_GT(s->cpu_percent, 20.0f);
  EXPECT_LT(s->cpu_percent, 110.0f);
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
