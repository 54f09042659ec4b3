#include "common/catch/prim/catch_planner.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ephor::catching {

const char* to_string(GoalReason reason) {
  switch (reason) {
    case GoalReason::kReady:
      return "ready";
    case GoalReason::kCatch:
      return "catch";
    case GoalReason::kRefined:
      return "refined";
    case GoalReason::kRefreshed:
      return "refreshed";
    case GoalReason::kReturnReady:
      return "return to ready";
    case GoalReason::kUnchanged:
      return "unchanged";
    case GoalReason::kTooSoon:
      return "too soon";
    case GoalReason::kHolding:
      return "holding";
    case GoalReason::kFrozen:
      return "frozen";
    case GoalReason::kWaiting:
      return "waiting";
    case GoalReason::kOutOfTime:
      return "out of time";
  }
  return "?";
}

CatchPlannerParams CatchPlannerParams::for_board(const BoardSpec& board,
                                                 const BoardPlacement& placement) {
  CatchPlannerParams p;
  const Eigen::Vector3d& e = placement.bottom_centre_w_mm;
  const double plane_z = e.z() - kCatchPlaneBelowEdgeMm;
  p.reach_min_w_mm =
      Eigen::Vector3d(e.x() - 350.0, e.y() - 0.5 * board.width_mm - 100.0, plane_z - 5.0);
  p.reach_max_w_mm =
      Eigen::Vector3d(e.x() + 50.0, e.y() + 0.5 * board.width_mm + 100.0, plane_z + 5.0);
  return p;
}

CatchPlannerParams PrimTuning::apply(CatchPlannerParams p) const {
  p.freeze_before_catch_s = freeze_ms / 1e3;
  p.hold_after_catch_us = static_cast<int64_t>(hold_ms * 1e3);
  p.max_sigma_mm = max_sigma_mm;
  p.commit_ahead_s = commit_ahead_s;
  p.min_interval_us = static_cast<int64_t>(reaim_ms * 1e3);
  p.resend_min_mm = resend_mm;
  p.resend_sigma_fraction = 0.5;
  p.refresh_min_mm = std::min(5.0, resend_mm);
  p.refresh_period_us = 200'000;
  p.move_s_per_sqrt_mm = move_s_per_sqrt_mm;
  p.commit_margin_s = commit_margin_s;
  return p;
}

CatchPlanner::CatchPlanner(const BoardSpec& board, const BoardPlacement& placement,
                           const CatchPlannerParams& params)
    : params_(params), ready_w_mm_(catching::ready_point_w_mm(board, placement)) {
  if (!params.reach_min_w_mm.allFinite() || !params.reach_max_w_mm.allFinite() ||
      (params.reach_min_w_mm.array() > params.reach_max_w_mm.array()).any()) {
    throw std::invalid_argument("CatchPlanner: the reachable box must be finite with min <= max");
  }
  if ((ready_w_mm_.array() < params.reach_min_w_mm.array()).any() ||
      (ready_w_mm_.array() > params.reach_max_w_mm.array()).any()) {
    throw std::invalid_argument(
        "CatchPlanner: the ready point (bottom centre of the board in the catch plane) is outside "
        "the reachable box");
  }
  if (!(params.resend_min_mm >= 0.0) || !(params.resend_sigma_fraction >= 0.0) ||
      !(params.refresh_min_mm >= 0.0) || params.refresh_period_us < 0 ||
      params.min_interval_us < 0 || params.hold_after_catch_us < 0 ||
      !(params.freeze_before_catch_s >= 0.0) || !(params.move_s_per_sqrt_mm >= 0.0) ||
      !(params.commit_margin_s >= 0.0)) {
    throw std::invalid_argument("CatchPlanner: thresholds and intervals must be >= 0");
  }
}

Eigen::Vector3d CatchPlanner::clamp(const Eigen::Vector3d& p_w_mm) const {
  return p_w_mm.cwiseMax(params_.reach_min_w_mm).cwiseMin(params_.reach_max_w_mm);
}

CatchGoal CatchPlanner::send(int64_t now_utime, const Eigen::Vector3d& wanted, GoalReason reason,
                             CatchGoal goal) {
  // The very first goal goes at once; after that the arm gets at most one
  // goal per min_interval_us (each one starts a new trajectory plan).
  if (has_goal_ && now_utime - last_send_utime_ < params_.min_interval_us) {
    goal.reason = GoalReason::kTooSoon;
    return goal;
  }
  has_goal_ = true;
  ++goal_id_;
  goal_w_mm_ = wanted;
  last_send_utime_ = now_utime;
  goal.send = true;
  goal.goal_id = goal_id_;
  goal.point_w_mm = goal_w_mm_;
  goal.reason = reason;
  return goal;
}

CatchGoal CatchPlanner::step(int64_t now_utime, const std::optional<CatchPrediction>& prediction,
                             const Eigen::Vector3d& cup_w_mm) {
  CatchGoal goal;
  goal.goal_id = goal_id_;
  goal.point_w_mm = goal_w_mm_;

  const bool coming =
      prediction && prediction->ball_id != finished_ball_id_ &&
      prediction->catch_point_w_mm.allFinite() && std::isfinite(prediction->sigma_mm) &&
      prediction->sigma_mm <= params_.max_sigma_mm && now_utime <= prediction->catch_utime &&
      1e-6 * static_cast<double>(prediction->catch_utime - now_utime) <= params_.commit_ahead_s;
  Eigen::Vector3d wanted = ready_w_mm_;
  GoalReason due = GoalReason::kUnchanged;
  if (coming) {
    wanted = prediction->catch_point_w_mm;
    goal.time_to_catch_s = 1e-6 * static_cast<double>(prediction->catch_utime - now_utime);
  }
  goal.wanted_w_mm = wanted;
  const Eigen::Vector3d clamped = clamp(wanted);
  goal.clamped_by_mm = (clamped - wanted).norm();
  goal.clamped = goal.clamped_by_mm > 0.0;
  goal.moved_mm = has_goal_ ? (clamped - goal_w_mm_).norm() : 0.0;

  if (coming) {
    goal.threshold_mm =
        std::max(params_.resend_min_mm, params_.resend_sigma_fraction * prediction->sigma_mm);
    if (goal_ball_id_ != prediction->ball_id) {
      due = GoalReason::kCatch;
    } else if (goal.moved_mm > goal.threshold_mm) {
      due = GoalReason::kRefined;
    } else if (goal.moved_mm > params_.refresh_min_mm &&
               now_utime - last_send_utime_ >= params_.refresh_period_us) {
      due = GoalReason::kRefreshed;
    }
    if ((due == GoalReason::kRefined || due == GoalReason::kRefreshed) &&
        goal.time_to_catch_s < params_.freeze_before_catch_s) {
      goal.reason = GoalReason::kFrozen;
      due = GoalReason::kUnchanged;
    }
    if (params_.move_s_per_sqrt_mm > 0.0) {
      goal.move_time_s = params_.move_s_per_sqrt_mm * std::sqrt((clamped - cup_w_mm).norm());
      if (due == GoalReason::kCatch &&
          goal.time_to_catch_s > goal.move_time_s + params_.commit_margin_s) {
        goal.reason = GoalReason::kWaiting;
        due = GoalReason::kUnchanged;
      } else if ((due == GoalReason::kRefined || due == GoalReason::kRefreshed) &&
                 goal.move_time_s > goal.time_to_catch_s) {
        goal.reason = GoalReason::kOutOfTime;
        due = GoalReason::kUnchanged;
      }
    }
    if (due != GoalReason::kUnchanged) {
      goal = send(now_utime, clamped, due, goal);
      if (goal.send) {
        goal_ball_id_ = prediction->ball_id;
      }
    }
    if (goal_ball_id_ == prediction->ball_id) goal_catch_utime_ = prediction->catch_utime;
  } else if (goal_ball_id_ >= 0) {
    // The current goal aimed at a ball whose catch time has passed (or whose
    // prediction went away): hold, then go back to the ready point.
    if (now_utime - goal_catch_utime_ < params_.hold_after_catch_us) {
      goal.reason = GoalReason::kHolding;
    } else {
      const int ball = goal_ball_id_;
      goal = send(now_utime, clamped, GoalReason::kReturnReady, goal);
      if (goal.send) {
        finished_ball_id_ = ball;
        goal_ball_id_ = -1;
      }
    }
  } else if (!has_goal_) {
    goal = send(now_utime, clamped, GoalReason::kReady, goal);
  }
  goal.cup_distance_mm = (cup_w_mm - goal.point_w_mm).norm();
  return goal;
}

}  // namespace ephor::catching
