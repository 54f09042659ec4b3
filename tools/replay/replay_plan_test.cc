#include "tools/replay/replay_plan.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "ephor/shepherd_blobs_t.hpp"
#include "ephor/shepherd_objects_t.hpp"

namespace ephor::replay {
namespace {

template <class T>
std::vector<uint8_t> encode(const T& msg) {
  std::vector<uint8_t> out(static_cast<size_t>(msg.getEncodedSize()));
  msg.encode(out.data(), 0, static_cast<int>(out.size()));
  return out;
}

TEST(ReplayPlanTest, VisionAndWorldModelAreFedCameraFramesAndWaitForObjects) {
  const ReplayPlan plan = make_replay_plan("worldmodel,vision");
  ASSERT_EQ(plan.processes.size(), 2u);
  EXPECT_EQ(plan.processes[0].name, "vision");
  EXPECT_EQ(plan.processes[0].replay_args, std::vector<std::string>{"--on-frame"});
  EXPECT_EQ(plan.frame_channel, "CAMERA");
  EXPECT_TRUE(plan.is_input("VISION_CMD"));
  EXPECT_FALSE(plan.is_input("BLOBS"));  // comes from the live vision, not the log
  EXPECT_EQ(plan.output_channels, (std::vector<std::string>{"BLOBS", "OBJECTS"}));
  EXPECT_EQ(plan.final_channel, "OBJECTS");
}

TEST(ReplayPlanTest, WorldModelAloneIsFedLoggedBlobs) {
  const ReplayPlan plan = make_replay_plan("worldmodel");
  EXPECT_EQ(plan.frame_channel, "BLOBS");
  EXPECT_EQ(plan.input_channels, std::vector<std::string>{"BLOBS"});
  EXPECT_EQ(plan.final_channel, "OBJECTS");
  EXPECT_EQ(make_replay_plan("vision").final_channel, "BLOBS");
}

TEST(ReplayPlanTest, BadProcessListsAreNamed) {
  EXPECT_THROW(make_replay_plan(""), std::invalid_argument);
  EXPECT_THROW(make_replay_plan("vision,vision"), std::invalid_argument);
  try {
    make_replay_plan("vision,planner");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'planner'"), std::string::npos);
  }
}

TEST(ReplayPlanTest, UtimeIsReadFromAnyMessage) {
  shepherd_blobs_t b{};
  b.utime = 1234567890123;
  const auto bytes = encode(b);
  EXPECT_EQ(message_utime(bytes.data(), static_cast<int>(bytes.size())), 1234567890123);
  EXPECT_EQ(message_utime(bytes.data(), 10), std::nullopt);
}

TEST(ReplayPlanTest, NormalisedOutputsDropOnlyTheReplaysOwnTimes) {
  shepherd_blobs_t b{};
  b.utime = 42;
  b.header.utime = 99;
  b.header.sender = "vision";
  b.header.seq = 7;
  b.processing_us = 812.5f;
  b.num_blobs = 1;
  b.blobs = {shepherd_blob_t{10.5f, 20.25f, 30, 1, 2, 3, 4}};
  const auto bytes = encode(b);
  const auto norm = normalised_output("BLOBS", bytes.data(), static_cast<int>(bytes.size()));
  shepherd_blobs_t back;
  ASSERT_EQ(back.decode(norm.data(), 0, static_cast<int>(norm.size())),
            static_cast<int>(norm.size()));
  EXPECT_EQ(back.utime, 42);
  EXPECT_EQ(back.header.utime, 0);
  EXPECT_EQ(back.header.seq, 7);
  EXPECT_EQ(back.processing_us, 0.0f);
  EXPECT_EQ(back.blobs[0].v, 20.25f);

  shepherd_objects_t o{};
  o.header.utime = 5;
  const auto obytes = encode(o);
  const auto onorm = normalised_output("OBJECTS", obytes.data(), static_cast<int>(obytes.size()));
  shepherd_objects_t oback;
  oback.decode(onorm.data(), 0, static_cast<int>(onorm.size()));
  EXPECT_EQ(oback.header.utime, 0);
  EXPECT_THROW(normalised_output("OBJECTS", bytes.data(), static_cast<int>(bytes.size())),
               std::invalid_argument);
}

}  // namespace
}  // namespace ephor::replay
