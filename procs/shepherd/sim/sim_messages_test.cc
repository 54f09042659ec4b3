// SimInputs (ephor-sim's bus handlers) and advance_to() (its physics task).

#include "procs/shepherd/sim/sim_messages.h"

#include <vector>

#include <gtest/gtest.h>

#include "common/shepherd/sim/simulator.h"

namespace ephor::sim {
namespace {

SimulatorConfig small_world() {
  SimulatorConfig c;
  c.world.sheep = 2;
  c.world.seed = 1;
  return c;
}

shepherd_sim_cmd_t command(int32_t sheep, bool reset, int32_t seed) {
  shepherd_sim_cmd_t m;
  m.sheep = sheep;
  m.reset = reset;
  m.seed = seed;
  return m;
}

TEST(SimInputs, ResetsOnTheRisingEdgeOrANewSeedOnly) {
  Simulator sim(small_world());
  SimInputs inputs;
  double clock_s = 0.0;
  advance_to(sim, clock_s, 0.1);
  EXPECT_TRUE(inputs.on_command(command(2, true, 5), sim));
  EXPECT_DOUBLE_EQ(sim.world().time_s(), 0.0);  // reset: time from zero
  advance_to(sim, clock_s, 0.15);
  EXPECT_TRUE(inputs.on_command(command(2, true, 5), sim));  // held: no reset
  EXPECT_GT(sim.world().time_s(), 0.0);
  EXPECT_TRUE(inputs.on_command(command(2, true, 6), sim));  // a new seed while set
  EXPECT_DOUBLE_EQ(sim.world().time_s(), 0.0);
}

TEST(SimInputs, RefusesAndCountsAHerdOutOfRange) {
  Simulator sim(small_world());
  SimInputs inputs;
  EXPECT_FALSE(inputs.on_command(command(kMaxSheep + 1, false, 0), sim));
  EXPECT_FALSE(inputs.on_command(command(-1, true, 3), sim));
  EXPECT_EQ(inputs.commands_refused(), 2);
  EXPECT_EQ(sim.world().sheep().size(), 2u);
  EXPECT_TRUE(inputs.on_command(command(0, false, 0), sim));
  EXPECT_EQ(sim.world().sheep().size(), 0u);
}

TEST(SimInputs, CountsAMalformedTrajectory) {
  SimInputs inputs;
  joint_trajectory_t m;
  m.seq = 7;
  m.num_points = 0;
  EXPECT_FALSE(inputs.on_trajectory(m));
  m.num_points = 1;
  m.t_s = {0.0f};
  m.q = {std::vector<double>(6, 0.0)};
  m.qd = {std::vector<double>(6, 0.0)};
  EXPECT_TRUE(inputs.on_trajectory(m));
  EXPECT_EQ(inputs.trajectories_received(), 2);
  EXPECT_EQ(inputs.trajectories_refused(), 1);
}

TEST(SimInputs, SwitchesTheToolLight) {
  Simulator sim(small_world());
  SimInputs inputs;
  shepherd_tool_light_t m;
  m.on = true;
  inputs.on_tool_light(m, sim);
  EXPECT_TRUE(sim.tool_light());
  m.on = false;
  inputs.on_tool_light(m, sim);
  EXPECT_FALSE(sim.tool_light());
  m.on = 2;  // any byte but 0 is true (crash-light-on-byte-2)
  inputs.on_tool_light(m, sim);
  EXPECT_TRUE(sim.tool_light());
}

TEST(AdvanceTo, StepsToTheClockAndSkipsAheadWhenFarBehind) {
  Simulator sim(small_world());
  double clock_s = 0.0;
  EXPECT_FALSE(advance_to(sim, clock_s, 0.0105));
  EXPECT_NEAR(clock_s, 0.010, 1e-9);
  EXPECT_NEAR(sim.world().time_s(), 0.010, 1e-9);
  EXPECT_TRUE(advance_to(sim, clock_s, 2.0));  // starved for 2 s: no burst
  EXPECT_NEAR(clock_s, 2.0, kPhysicsStepS + 1e-9);
  EXPECT_LT(sim.world().time_s(), 0.0125);
}

}  // namespace
}  // namespace ephor::sim
