#pragma once
// CatchLoop: the whole catching system in simulated time, deterministic and
// free of the machine's load (paper 000): the simulator's world
// (common/catch/sim: board, ball, camera, the run of balls and its judge and
// oracle), the vision and world model libraries frame by frame as
// ephor-catch-vision and ephor-catch-worldmodel run them, Prim's library
// (CatchPlanner with ephor-catch-prim's tuning), and the arm as ephor-arm and
// ephor-catch-sim execute a cup goal: the motion ephor-arm plans
// (CatchCell::plan_move: the shared MotionPlanner at the PUMA 560's joint
// limits, from rest at the arm's joints when the goal arrives) followed by
// the shared servo layer (ArmServo) from wherever the arm is. Each ball is
// judged by the simulator's CatchJudge and scored by the monitor's
// CatchSummary, so the figures are those of `tools/ephor run
// deploy/catch.pbtxt --summary F`: caught, oracle_reachable, the missed
// balls' kinds.
//
// Time: the world's clock (s) in 1 ms steps, as ephor-catch-sim; camera
// frames every 1/60 s; a message's utime is 1 s + the world time of its
// state (us). The processes' delays are fixed: frame capture to Prim
// (perception_latency_s: the live throughput p50 is 3-6 ms), Prim's goal to
// ephor-arm's planning (command_latency_s: comm relays every 10 ms), the plan
// to the servo following it (trajectory_latency_s: ARM_TRAJECTORY, then the
// simulator's 2 ms physics task). Processing itself takes no simulated time.
//
// Start-up as the live run: the arm parked out of view, ten frames for the
// circles and IPPE, then the board's placement from the three touched points
// (CATCH_SURVEY), the pegs as measured (CATCH_PEGS), Prim's first goal (the
// ready point), the first ball at first_release_s.
//
// Prim modes: kPrediction is ephor-catch-prim (the world model's predicted
// catch point); kCover the same planner aimed at the cover of the
// prediction's spread (ExitSpread: the catch-plane point within the cup's
// capture radius of the most sampled exits; model.spread.samples, 32 when
// 0); kOracle sends the true catch point at the release and
// nothing else (the loop's own ceiling: what the arm as executed catches of
// oracle_reachable with a perfect, instant prediction).
//
// Not thread-safe; run() once per object. Throws std::runtime_error when the
// board's circles or pose are not found (the seed needs --circle-windows
// live).

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/catch/board_model.h"
#include "common/catch/prim/catch_planner.h"
#include "common/catch/worldmodel/ball_world_model.h"
#include "common/geometry/workcell.h"

namespace ephor::catching {

enum class PrimMode { kPrediction, kCover, kOracle };
const char* to_string(PrimMode mode);

struct CatchLoopOptions {
  uint64_t seed = 1;
  int balls = 20;
  double gap_s = 1.0;            // ephor-catch-sim's --gap-s
  double first_release_s = 6.0;  // ephor-catch-sim's --first-release-s
  double perception_latency_s = 0.005;
  double command_latency_s = 0.010;
  double trajectory_latency_s = 0.004;
  // Feed the world model the ball centre's true projection (the vision's
  // ceiling), not the vision's centroid.
  bool true_centre = false;
  PrimMode prim = PrimMode::kCover;
  PrimTuning tuning;
  // acquire_max_y_mm is set to ephor-catch-worldmodel's 150 mm.
  BallWorldModelParams model;
  // A line per Prim cycle with a ball (world time, time to catch, the catch
  // point Prim got and the true one along W's y, the cover's fraction, the
  // cup) and per goal, to stdout.
  bool trace = false;
};

struct CatchLoopResult {
  uint64_t seed = 0;
  int balls = 0;
  int caught = 0;
  int oracle_reachable = 0;
  int caught_reachable = 0;
  int goals = 0;          // cup goals Prim sent
  int plans_refused = 0;  // goals ephor-arm's planner refused
  int servo_faults = 0;   // trajectories the servo flagged (it keeps following)
  // The monitor's summary (CatchSummary::to_json): per-ball outcomes with
  // their miss kinds, position error.
  nlohmann::json summary;
};

class CatchLoop {
 public:
  CatchLoop(const BoardSpec& board, const geometry::Workcell& workcell, CatchLoopOptions options);
  CatchLoopResult run();

 private:
  BoardSpec board_;
  geometry::Workcell workcell_;
  CatchLoopOptions options_;
};

}  // namespace ephor::catching
