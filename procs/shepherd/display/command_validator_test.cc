#include "procs/shepherd/display/command_validator.h"

#include <gtest/gtest.h>

namespace ephor::display {
namespace {

class CommandValidatorTest : public ::testing::Test {
 protected:
  CommandResult run(const std::string& cmd, std::map<std::string, std::string> params) {
    return validator_.validate(cmd, params, current_);
  }
  CommandValidator validator_{512, 482};
  Controls current_ = [] {
    Controls c;
    c.vision = {false, 1, 1, 120};  // trackify, axis scan, fixed threshold
    c.sim = {5, 7};
    c.planner = "single";
    return c;
  }();
};

TEST_F(CommandValidatorTest, PauseKeepsTheRestOfTheVisionState) {
  const auto r = run("pause", {{"value", "true"}});
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_EQ(r.target, Target::kVision);
  EXPECT_TRUE(r.controls.vision.paused);
  EXPECT_EQ(r.controls.vision.mode, 1);
  EXPECT_EQ(r.controls.vision.scan, 1);
  EXPECT_EQ(r.controls.vision.threshold, 120);
}

TEST_F(CommandValidatorTest, ModeAndScanSwitch) {
  auto r = run("mode", {{"value", "blobify"}});
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.controls.vision.mode, 0);
  EXPECT_EQ(r.controls.vision.scan, 1);
  r = run("scan", {{"value", "full"}});
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.controls.vision.scan, 0);
  EXPECT_EQ(r.controls.vision.mode, 1);
}

TEST_F(CommandValidatorTest, SheepKeepsTheSeedAndChecksTheRange) {
  auto r = run("sheep", {{"value", "3"}});
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.target, Target::kSim);
  EXPECT_EQ(r.controls.sim.sheep, 3);
  EXPECT_EQ(r.controls.sim.seed, 7);
  for (const char* bad : {"-1", "65", "3.5", "3x", "", " 3", "99999999999999"}) {
    r = run("sheep", {{"value", bad}});
    EXPECT_FALSE(r.ok) << bad;
    EXPECT_NE(r.reason.find("0..64"), std::string::npos) << r.reason;
  }
}

TEST_F(CommandValidatorTest, PlannerKinds) {
  EXPECT_EQ(run("planner", {{"value", "lookahead"}}).controls.planner, "lookahead");
  const auto r = run("planner", {{"value", "greedy"}});
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("greedy"), std::string::npos);
}

TEST_F(CommandValidatorTest, BoxMustLieInsideTheImage) {
  auto r = run("box", {{"u", "100.5"}, {"v", "200"}, {"half", "20"}});
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_EQ(r.target, Target::kBox);
  EXPECT_TRUE(r.controls.box.visible);
  EXPECT_DOUBLE_EQ(r.controls.box.u, 100.5);
  EXPECT_DOUBLE_EQ(r.controls.box.half_size_px, 20.0);
  EXPECT_FALSE(run("box", {{"u", "512"}, {"v", "10"}}).ok);
  EXPECT_FALSE(run("box", {{"u", "nan"}, {"v", "10"}}).ok);
  EXPECT_FALSE(run("box", {{"u", "inf"}, {"v", "10"}}).ok);
  EXPECT_FALSE(run("box", {{"u", "10"}}).ok);
  EXPECT_FALSE(run("box", {{"u", "10"}, {"v", "10"}, {"half", "0"}}).ok);
  r = run("box", {{"u", "10"}, {"v", "10"}, {"visible", "false"}});
  ASSERT_TRUE(r.ok);
  EXPECT_FALSE(r.controls.box.visible);
}

TEST_F(CommandValidatorTest, UnknownCommandsAndBadValuesAreRefusedWithAReason) {
  struct Case {
    std::string cmd;
    std::map<std::string, std::string> params;
    std::string reason_part;
  };
  const std::vector<Case> cases = {
      {"reboot", {{"value", "1"}}, "unknown command 'reboot'"},
      {"pause", {}, "needs a value"},
      {"pause", {{"value", "maybe"}}, "maybe"},
      {"mode", {{"value", "TRACKIFY"}}, "TRACKIFY"},
      {"scan", {{"value", ""}}, "neither full nor axis"},
  };
  for (const auto& c : cases) {
    const auto r = run(c.cmd, c.params);
    EXPECT_FALSE(r.ok) << c.cmd;
    EXPECT_EQ(r.target, Target::kNone);
    EXPECT_NE(r.reason.find(c.reason_part), std::string::npos) << r.reason;
  }
}

}  // namespace
}  // namespace ephor::display
