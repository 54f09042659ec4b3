#pragma once
// CatchPlanner: NASREM's manipulator Primitive level (Prim) for ball
// catching (paper 000; Wavering, NIST TN 1256): from the world model's
// newest prediction it decides where the cup should wait. The arm process
// plans a trajectory for every goal it receives, so the planner sends a new
// goal only when it matters, never more often than a minimum interval.
//
//   no ball yet             -> the ready point (ready_point_w_mm, board_model.h): the
//                              board dropped vertically to the catch plane
//   a prediction            -> the predicted catch point (in the catch plane)
//   the prediction moves    -> re-send when it moved by more than
//                              max(resend_min_mm, resend_sigma_fraction *
//                              sigma), or by more than refresh_min_mm once
//                              refresh_period_us passed since the last goal
//   the catch is near       -> no re-aim within freeze_before_catch_s of the
//                              predicted catch (the arm cannot move the cup
//                              usefully in that time, and a new goal makes it
//                              brake; the last predictions near the edge are
//                              the ones the cup in view corrupts)
//   the ball has gone       -> hold hold_after_catch_us after the predicted
//   (catch time passed)        catch time, then return to the ready point
//
// Every goal is clamped to the reachable box in front of the board's bottom
// edge (configurable); a clamped goal says so. The cup is carried with the
// tool pointing down, so a goal is a point (its opening centre, W, mm).
//
// Times: utime (us) on the clock of the predictions. Not thread-safe; one
// owner. Expected outcomes (no prediction, out of reach) are values.

#include <cstdint>
#include <limits>
#include <optional>

#include <Eigen/Core>

#include "common/catch/board_model.h"

namespace ephor::catching {

// The world model's newest prediction, as the planner needs it.
struct CatchPrediction {
  int ball_id = 0;          // changes when a new ball is acquired
  int64_t catch_utime = 0;  // when the ball crosses the catch plane
  Eigen::Vector3d catch_point_w_mm = Eigen::Vector3d::Zero();  // in the catch plane, W
  double sigma_mm = 0.0;  // 1-sigma of the catch point (worst direction)
};

struct CatchPlannerParams {
  // The reachable box (W, mm), corners inclusive.
  Eigen::Vector3d reach_min_w_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d reach_max_w_mm = Eigen::Vector3d::Zero();
  double resend_min_mm = 5.0;
  double resend_sigma_fraction = 0.3;
  double refresh_min_mm = 2.0;          // smaller changes are never re-sent
  int64_t refresh_period_us = 100'000;  // a smaller change is re-sent after this long
  int64_t min_interval_us = 30'000;     // between two goals, whatever the reason
  int64_t hold_after_catch_us = 500'000;
  // A prediction less sure than this (sigma_mm) is not chased: the cup stays
  // where it is (the ready point hedges best). Infinity = chase every one.
  double max_sigma_mm = std::numeric_limits<double>::infinity();
  // A catch further ahead than this is not chased yet: the ball has pegs to
  // pass, which the prediction's sigma does not know of. Infinity = no wait.
  double commit_ahead_s = std::numeric_limits<double>::infinity();
  // No re-aim (kRefined, kRefreshed) for a catch closer than this, s; the
  // first goal for a ball still goes. 0 = re-aim until the catch.
  double freeze_before_catch_s = 0.0;
  // Commit late (move_s_per_sqrt_mm > 0). The arm's time to move the cup a
  // distance d (mm) from rest, as move_s_per_sqrt_mm * sqrt(d) s: ephor-arm's
  // plans for the PUMA 560 in the catching cell are acceleration-limited by
  // the joints (CatchCell::plan_move from the ready point, seeds 1-3: 0.27-0.29
  // s for 10 mm, 0.49-0.52 s for 30 mm, 0.88-0.96 s for 100 mm, 1.67-2.05 s
  // for 400 mm: 0.089 s/sqrt(mm)), so a re-aim costs as much as a move and
  // every later prediction is better than an earlier one. The first goal for
  // a ball waits (kWaiting) until the predicted catch is no further ahead
  // than the move time from the cup to the predicted point plus
  // commit_margin_s; a re-aim goes only if that time still fits before the
  // catch (else kOutOfTime). 0 = no model: chase at once.
  double move_s_per_sqrt_mm = 0.0;
  double commit_margin_s = 0.1;

  // Defaults for a board: the box spans the board's width plus 100 mm on
  // each side (y of W), from 50 mm behind to 350 mm in front of the bottom
  // edge (x of W: the ball flies towards -x), and the catch plane +/- 5 mm
  // in z.
  static CatchPlannerParams for_board(const BoardSpec& board, const BoardPlacement& placement);
};

// ephor-catch-prim's flags (--commit-ahead-s, --reaim-ms, --hold-ms,
// --resend-mm, --freeze-ms, --max-sigma-mm, --move-s-per-sqrt-mm,
// --commit-margin-s) and their defaults, as one value the process and the
// closed-loop harness (procs/catch/bench) share.
//
// Each goal makes ephor-arm plan a new motion from rest wherever the arm is
// (a re-aim brakes it), and the arm is slow for short moves (0.5 s for 30
// mm): so commit late (move_s_per_sqrt_mm: the first goal for a ball goes
// when the modelled move from the cup just fits before the predicted catch,
// on the newest prediction; a re-aim only while it still fits), chase a
// prediction only while its sigma is under max_sigma_mm (with the world
// model's --spread-samples, the standard deviation of the sampled exits: a
// spread this wide is a guess, and the ready point hedges it best), re-aim
// at most every reaim_ms for a change of at least resend_mm or half a
// sigma; no re-aim within freeze_ms of the catch. After a ball the cup goes
// back to the ready point hold_ms after the predicted catch: soon, because
// the move back takes up to a second and the arm moving in view while the
// next ball is released hides that ball from the vision (measured: 4 of 10
// balls of seed 2 never tracked with 500 ms).
//
// The defaults were chosen in ephor-catch-loop (seeds 1-5 x 20 balls, the
// world model with --spread-samples 32), 2026-11-28: caught of
// oracle_reachable 19/54 chasing at once (commit_ahead_s 1, max_sigma_mm
// 150), 22/54 committing late (commit_ahead_s 10), 26/54 with max_sigma_mm
// 100 (21/54 with 30, 24/54 with 60).
struct PrimTuning {
  double commit_ahead_s = 10.0;
  double reaim_ms = 250.0;
  double hold_ms = 150.0;
  double resend_mm = 15.0;
  double freeze_ms = 150.0;
  // A prediction with a larger sigma (mm) is not chased (CatchPlannerParams).
  double max_sigma_mm = 100.0;
  // Commit late (see CatchPlannerParams::move_s_per_sqrt_mm); 0 = off.
  double move_s_per_sqrt_mm = 0.089;
  double commit_margin_s = 0.1;
  // The parameters for `p` (for_board's box) with these settings.
  CatchPlannerParams apply(CatchPlannerParams p) const;
};

enum class GoalReason {
  kReady,        // the first goal: wait at the ready point
  kCatch,        // the first goal for a ball's prediction
  kRefined,      // the prediction moved by more than the threshold
  kRefreshed,    // a smaller change, sent after refresh_period_us
  kReturnReady,  // the ball has gone: back to the ready point
  kUnchanged,    // no new goal: the current one still holds
  kTooSoon,      // a new goal is due but min_interval_us has not passed
  kHolding,      // no new goal: the ball has gone, holding before returning
  kFrozen,       // no re-aim: the catch is within freeze_before_catch_s
  kWaiting,      // commit late: the arm can still get there later, wait for better predictions
  kOutOfTime,    // commit late: no re-aim, the arm could not get there before the catch
};
const char* to_string(GoalReason reason);

struct CatchGoal {
  bool send = false;  // a new goal to send this cycle
  int goal_id = 0;    // of the current goal (the new one if send); 0 = none yet
  Eigen::Vector3d point_w_mm = Eigen::Vector3d::Zero();  // the current goal, W
  GoalReason reason = GoalReason::kUnchanged;
  bool clamped = false;                                   // the wanted point was out of reach
  double clamped_by_mm = 0.0;                             // how far the clamp moved it
  Eigen::Vector3d wanted_w_mm = Eigen::Vector3d::Zero();  // before clamping
  double moved_mm = 0.0;         // wanted (clamped) point vs the current goal
  double threshold_mm = 0.0;     // the re-send threshold that applied
  double cup_distance_mm = 0.0;  // from the cup to the goal
  double time_to_catch_s = 0.0;  // 0 without a prediction
  double move_time_s = 0.0;      // commit late: the modelled move from the cup to the wanted point
};

class CatchPlanner {
 public:
  // Throws std::invalid_argument for an empty box, a ready point outside it
  // or negative thresholds and intervals.
  CatchPlanner(const BoardSpec& board, const BoardPlacement& placement,
               const CatchPlannerParams& params);

  // One cycle: `prediction` is the newest (nullopt when there is none),
  // `cup_w_mm` the tool tip now.
  CatchGoal step(int64_t now_utime, const std::optional<CatchPrediction>& prediction,
                 const Eigen::Vector3d& cup_w_mm);

  const Eigen::Vector3d& ready_point_w_mm() const { return ready_w_mm_; }
  const CatchPlannerParams& params() const { return params_; }
  // The point clamped to the reachable box.
  Eigen::Vector3d clamp(const Eigen::Vector3d& p_w_mm) const;

 private:
  CatchGoal send(int64_t now_utime, const Eigen::Vector3d& wanted, GoalReason reason,
                 CatchGoal goal);

  CatchPlannerParams params_;
  Eigen::Vector3d ready_w_mm_;
  bool has_goal_ = false;
  int goal_id_ = 0;
  Eigen::Vector3d goal_w_mm_ = Eigen::Vector3d::Zero();
  int64_t last_send_utime_ = 0;
  int goal_ball_id_ = -1;         // the ball the current goal aims at; -1 = the ready point
  int64_t goal_catch_utime_ = 0;  // its newest predicted catch time
  int finished_ball_id_ = -1;     // the ball we returned from: its predictions are ignored
};

}  // namespace ephor::catching
