#include "procs/catch/bench/catch_loop.h"

#include <array>
#include <cmath>
#include <deque>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <opencv2/core.hpp>

#include "common/arm/arm_servo.h"
#include "common/catch/board_survey.h"
#include "common/catch/sim/ball_sequence.h"
#include "common/catch/sim/board_renderer.h"
#include "common/catch/sim/board_world.h"
#include "common/catch/sim/catch_cell.h"
#include "common/catch/sim/catch_judge.h"
#include "common/catch/sim/catch_scenario.h"
#include "common/catch/summary/catch_summary.h"
#include "common/catch/vision/ball_window.h"
#include "common/catch/vision/board_pose_estimator.h"
#include "common/catch/vision/circle_finder.h"
#include "common/catch/vision/motion_centroid.h"

namespace ephor::catching {

const char* to_string(PrimMode mode) {
  switch (mode) {
    case PrimMode::kPrediction:
      return "prediction";
    case PrimMode::kCover:
      return "cover";
    case PrimMode::kOracle:
      return "oracle";
  }
  return "?";
}

CatchLoop::CatchLoop(const BoardSpec& board, const geometry::Workcell& workcell,
                     CatchLoopOptions options)
    : board_(board), workcell_(workcell), options_(std::move(options)) {
  if (options_.balls < 1) throw std::invalid_argument("CatchLoop: balls must be >= 1");
  if (!(options_.perception_latency_s >= 0.0) || !(options_.command_latency_s >= 0.0) ||
      !(options_.trajectory_latency_s >= 0.0))
    throw std::invalid_argument("CatchLoop: the latencies must be >= 0 s");
}

namespace {

constexpr double kStepS = 0.001;  // ephor-catch-sim's physics step
constexpr double kFrameS = 1.0 / 60.0;
constexpr int kInitFrames = 10;  // ephor-catch-vision's

int64_t utime_of(double t_s) { return 1'000'000 + std::llround(t_s * 1e6); }

// Messages in flight between the processes, due at a world time.
struct WorldEvent {
  double at_s;
  std::optional<CatchPrediction> prediction;
  double cover_fraction = std::nan("");  // for the trace
};
struct GoalEvent {
  double at_s;
  Eigen::Vector3d point_w_mm;
};
struct TrajectoryEvent {
  double at_s;
  sim::JointTrajectory trajectory;
};

}  // namespace

CatchLoopResult CatchLoop::run() {
  const uint64_t seed = options_.seed;
  const CatchScenario scenario = CatchScenario::draw(seed, board_);
  const CatchCell cell(scenario, workcell_);
  BoardRenderer renderer(scenario, CupSpec{}, seed);
  BoardWorld world(scenario);
  sim::ArmServo servo(cell.puma().limits(), cell.park_joints());
  BallSequence balls(scenario, options_.balls, options_.gap_s, options_.first_release_s);
  const CatchJudge judge(scenario.board, scenario.placement);
  CatchSummary summary(static_cast<int64_t>(seed));
  CatchLoopResult result;
  result.seed = seed;

  // The board in W from the three touched points, as Prim and the world
  // model take it from CATCH_SURVEY.
  const CatchScenario::TouchedPoints touched = scenario.touched_points();
  std::string why;
  const auto placement = placement_from_survey(board_, touched.board_mm, touched.world_mm, why);
  if (!placement) throw std::runtime_error("seed " + std::to_string(seed) + ": survey: " + why);
  CatchPlanner planner(board_, *placement,
                       options_.tuning.apply(CatchPlannerParams::for_board(board_, *placement)));

  // Perception as ephor-catch-vision and ephor-catch-worldmodel run it.
  const CircleFinder finder(board_, scenario.intrinsics, {});
  const BoardPoseEstimator estimator(board_, scenario.intrinsics);
  MotionCentroid motion;
  std::optional<BallWindow> window;
  std::optional<BallWorldModel> model;
  std::vector<cv::Mat> init_frames;
  cv::Mat image;

  std::deque<WorldEvent> world_events;
  std::deque<GoalEvent> goal_events;
  std::deque<TrajectoryEvent> trajectory_events;
  int64_t trajectory_seq = 0;
  int oracle_ball = -1;  // kOracle: the ball whose catch point was sent
  bool oracle_ready_sent = false;
  double t = 0.0, next_frame_t = 0.0;

  auto send_goal = [&](double now_s, const Eigen::Vector3d& point) {
    ++result.goals;
    goal_events.push_back({now_s + options_.command_latency_s, point});
  };

  // One camera frame at world time t: the truth to the monitor, then vision
  // and world model, whose output reaches Prim perception_latency_s later.
  auto camera_frame = [&] {
    const BallState s = world.state();
    std::optional<Eigen::Vector3d> ball_b;
    if (s.on_board) ball_b = s.position_b_mm;
    const std::optional<Eigen::Vector2d> true_px =
        renderer.render(ball_b, cell.arm_view(servo.state().q), image);
    const int64_t utime = utime_of(t);
    const bool rolling = balls.phase() == BallSequence::Phase::kRolling;
    const auto& last = balls.last();
    summary.on_truth(utime, rolling, s.position_b_mm.head<2>(), last ? last->ball : -1,
                     last && last->caught, last && last->oracle_reachable,
                     last ? last->reason : std::string(), scenario.board_to_camera);
    const auto& expected = balls.expected_exit();
    summary.on_ball_truth(utime, balls.ball(), rolling, s.position_b_mm.head<2>(),
                          expected ? expected->x_b_mm : std::nan(""),
                          expected ? utime_of(expected->time_s) : 0);

    if (!model) {
      init_frames.push_back(image.clone());
      if (static_cast<int>(init_frames.size()) < kInitFrames) return;
      const CircleFinderResult circles = finder.find(init_frames);
      if (!circles.found)
        throw std::runtime_error("seed " + std::to_string(seed) +
                                 ": circles not found: " + circles.problem);
      std::array<Eigen::Vector2d, 4> c;
      for (size_t k = 0; k < 4; ++k) c[k] = circles.circles[k].centroid_px;
      const BoardPoseResult pose = estimator.estimate(c);
      if (!pose.ok)
        throw std::runtime_error("seed " + std::to_string(seed) + ": board pose: " + pose.problem);
      summary.on_board_pose(pose.board_to_camera);
      window.emplace(board_, scenario.intrinsics, pose.board_to_camera,
                     BallWindowOptions{24.0, 1.0 / 30.0, 0.1});
      BallWorldModelParams params = options_.model;
      params.acquire_max_y_mm = 150.0;
      if (options_.prim == PrimMode::kCover && params.spread.samples < 1)
        params.spread.samples = 32;
      model.emplace(board_, *placement, scenario.intrinsics, pose.board_to_camera, params);
      model->set_pegs(scenario.measured_pegs(), 0.5 * scenario.peg_diameter_mm);
      return;
    }
    // The window around the world model's newest output, carried forward.
    std::optional<cv::Rect> w;
    const BallFrame& previous = model->last();
    if (model->frames() > 0 && previous.status == BallStatus::kTracking)
      w = window->around(previous.position_b_mm, previous.velocity_b_mm_s,
                         static_cast<double>(utime - previous.utime) / 1e6);
    const MotionMeasurement m = motion.process(image, w);
    std::optional<Eigen::Vector2d> centroid;
    if (m.found && m.centroid_px.allFinite()) centroid = m.centroid_px;
    if (options_.true_centre) centroid = true_px;
    const BallFrame& f = model->update(utime, centroid);

    std::optional<Eigen::Vector2d> tracked;
    if (f.status == BallStatus::kTracking) tracked = f.position_b_mm;
    summary.on_world(utime, 1e3 * options_.perception_latency_s, tracked);
    // The exit Prim aims at, as ephor-catch-worldmodel publishes it.
    const bool cover = options_.prim == PrimMode::kCover && f.has_spread;
    summary.on_prediction(utime, f.status == BallStatus::kTracking, f.has_prediction,
                          !f.has_prediction ? std::nan("")
                          : cover           ? f.spread.cover_exit_x_b_mm
                                            : f.exit.exit_x_b_mm,
                          tracked);

    WorldEvent e{t + options_.perception_latency_s, std::nullopt};
    if (f.has_prediction && f.status != BallStatus::kNoBall) {
      CatchPrediction p;
      p.ball_id = f.ball_id;
      p.catch_utime = f.catch_utime;
      p.catch_point_w_mm = f.exit.catch_point_w_mm;
      p.sigma_mm = f.exit.sigma_exit_x_mm;
      if (cover) e.cover_fraction = f.spread.cover_fraction;
      if (cover) {
        p.sigma_mm = f.spread.exit_x_sd_mm;
        p.catch_point_w_mm = f.spread.cover_point_w_mm;
        p.catch_utime = f.cover_catch_utime;
      }
      if (p.catch_point_w_mm.allFinite() && std::isfinite(p.sigma_mm)) e.prediction = p;
    }
    world_events.push_back(e);
  };

  // Each simulated ball takes at most the stall limit on the board (10 s),
  // the gap and the arm's wait (3 s) before its release.
  const double limit_s = options_.first_release_s + 20.0 + options_.balls * (14.0 + options_.gap_s);
  double done_at_s = -1.0;
  bool fault_counted = false;
  while (t < limit_s) {
    // The messages due now, in the order they flow.
    while (!world_events.empty() && world_events.front().at_s <= t + 1e-9) {
      const WorldEvent e = world_events.front();
      world_events.pop_front();
      if (options_.prim == PrimMode::kOracle) continue;
      const Eigen::Vector3d cup = cell.cup_w_mm(servo.state().q);
      const CatchGoal g = planner.step(utime_of(e.at_s), e.prediction, cup);
      if (g.send) send_goal(e.at_s, g.point_w_mm);
      if (options_.trace && (e.prediction || g.send)) {
        const auto& x = balls.expected_exit();
        const double true_y = balls.phase() != BallSequence::Phase::kWaiting && x
                                  ? judge.catch_plane_crossing(*x).point_w_mm.y()
                                  : std::nan("");
        std::cout << fmt::format(
            "  t {:.3f} ball {} to catch {:.3f} s: aim y {:.0f} (true {:.0f}) sigma {:.0f} "
            "cover {:.2f} | cup y {:.0f} x {:.0f}{}\n",
            e.at_s, balls.ball(),
            e.prediction ? 1e-6 * (e.prediction->catch_utime - utime_of(e.at_s)) : 0.0,
            e.prediction ? e.prediction->catch_point_w_mm.y() : std::nan(""), true_y,
            e.prediction ? e.prediction->sigma_mm : std::nan(""), e.cover_fraction, cup.y(),
            cup.x(),
            g.send ? fmt::format(" GOAL {} ({:.0f}, {:.0f}) {}", g.goal_id, g.point_w_mm.x(),
                                 g.point_w_mm.y(), to_string(g.reason))
                   : std::string());
      }
    }
    if (options_.prim == PrimMode::kOracle && model) {
      if (!oracle_ready_sent) {
        send_goal(t, planner.ready_point_w_mm());
        oracle_ready_sent = true;
      }
      if (balls.phase() == BallSequence::Phase::kRolling && oracle_ball != balls.ball() &&
          balls.expected_exit()) {
        oracle_ball = balls.ball();
        send_goal(t, judge.catch_plane_crossing(*balls.expected_exit()).point_w_mm);
      }
      if (balls.last() && balls.last()->ball == oracle_ball && oracle_ball >= 0 &&
          balls.phase() != BallSequence::Phase::kRolling) {
        send_goal(t, planner.ready_point_w_mm());
        oracle_ball = -2 - oracle_ball;  // returned; never equal to a ball index
      }
    }
    while (!goal_events.empty() && goal_events.front().at_s <= t + 1e-9) {
      const GoalEvent g = goal_events.front();
      goal_events.pop_front();
      const arm::MotionPlan plan = cell.plan_move(servo.state().q, g.point_w_mm);
      if (!plan.ok) {
        ++result.plans_refused;
        continue;
      }
      sim::JointTrajectory traj;
      traj.seq = ++trajectory_seq;
      for (const auto& p : plan.trajectory.points) {
        traj.t_s.push_back(static_cast<double>(static_cast<float>(p.t_s)));  // the message's float
        traj.q.push_back(p.q);
        traj.qd.push_back(p.qd);
      }
      trajectory_events.push_back({g.at_s + options_.trajectory_latency_s, std::move(traj)});
    }
    while (!trajectory_events.empty() && trajectory_events.front().at_s <= t + 1e-9) {
      servo.follow(trajectory_events.front().trajectory);
      trajectory_events.pop_front();
      fault_counted = false;
    }

    // One step of ephor-catch-sim: servo, board, the run of balls.
    servo.step(kStepS);
    world.step(kStepS);
    t += kStepS;
    balls.step(world, cell, servo.state().q, world.time_s(),
               servo.state().qd.cwiseAbs().maxCoeff() < 0.01);
    if (servo.state().fault && !fault_counted) {
      ++result.servo_faults;
      fault_counted = true;
    }
    if (t + 1e-9 >= next_frame_t) {
      next_frame_t += kFrameS;
      camera_frame();
    }
    if (balls.phase() == BallSequence::Phase::kDone) {
      if (done_at_s < 0.0) done_at_s = t;
      if (t - done_at_s > 0.1) break;  // a few frames: the monitor takes the last outcome
    }
  }
  result.balls = balls.done();
  result.caught = balls.caught();
  result.oracle_reachable = balls.oracle_reachable();
  result.summary = summary.to_json();
  result.caught_reachable = result.summary.value("caught_of_oracle_reachable", 0);
  return result;
}

}  // namespace ephor::catching
