// Bus tests over LCM's in-process memq:// provider: no network needed.
#include "common/lcm/bus.h"

#include <cmath>

#include <gtest/gtest.h>

#include "ephor/task_trigger_t.hpp"

namespace ephor {
namespace {

ephor::task_trigger_t trigger(const std::string& task) {
  ephor::task_trigger_t t{};
  t.utime = 1;
  t.process = "p";
  t.task = task;
  return t;
}

TEST(Bus, ResolvesUrlFromFlagThenEnvThenDefault) {
  EXPECT_EQ(resolve_lcm_url("memq://"), "memq://");
  setenv("LCM_DEFAULT_URL", "udpm://239.255.76.67:7700?ttl=0", 1);
  EXPECT_EQ(resolve_lcm_url(""), "udpm://239.255.76.67:7700?ttl=0");
  unsetenv("LCM_DEFAULT_URL");
  EXPECT_EQ(resolve_lcm_url(""), kDefaultLcmUrl);
}

TEST(Bus, RejectsUnknownProviderWithUrlInMessage) {
  try {
    Bus bus("nosuchprovider://x", "t");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("nosuchprovider://x"), std::string::npos);
  }
}

TEST(Bus, PublishFillsHeaderAndMailboxKeepsNewest) {
  Bus bus("memq://", "tester");
  auto box = bus.mailbox<ephor::task_trigger_t>("T");
  auto a = trigger("a");
  auto b = trigger("b");
  ASSERT_TRUE(bus.publish("T", a));
  ASSERT_TRUE(bus.publish("T", b));
  while (bus.handle(0)) {
  }
  auto got = box->take();
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->task, "b");
  EXPECT_EQ(got->header.sender, "tester");
  EXPECT_EQ(got->header.seq, 1);  // second message on this channel
  EXPECT_GT(got->header.utime, 0);
  EXPECT_EQ(box->overwritten(), 1u);
}

TEST(Bus, GarbageIsCountedNotFatal) {
  Bus bus("memq://", "tester");
  int calls = 0;
  bus.subscribe<ephor::task_trigger_t>("T", [&](const ephor::task_trigger_t&) { ++calls; });
  const uint8_t garbage[] = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  ASSERT_TRUE(bus.publish_raw("T", garbage, sizeof garbage));
  while (bus.handle(0)) {
  }
  EXPECT_EQ(calls, 0);
  EXPECT_EQ(bus.counters("T").decode_errors, 1u);
}

TEST(Bus, ThrowingHandlerIsCountedAndBusKeepsWorking) {
  Bus bus("memq://", "tester");
  int calls = 0;
  bus.subscribe<ephor::task_trigger_t>("T", [&](const ephor::task_trigger_t& t) {
    ++calls;
    if (t.task == "bad") throw std::invalid_argument("bad task");
  });
  auto bad = trigger("bad");
  auto good = trigger("good");
  bus.publish("T", bad);
  bus.publish("T", good);
  while (bus.handle(0)) {
  }
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(bus.counters("T").handler_errors, 1u);
  EXPECT_EQ(bus.counters("T").received, 2u);
}

}  // namespace
}  // namespace ephor
