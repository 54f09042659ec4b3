#include "procs/rambo/planner/planner_task.h"

#include <algorithm>
#include <cmath>

#include <spdlog/spdlog.h>

#include "common/rambo/prediction_message.h"

namespace ephor::rambo {

namespace {
// ARM_GOAL to the arm's servo through comm, about: a reaching trajectory
// starts where the arm will be then, s.
constexpr double kLatencyS = 0.03;
// No re-plan this close before a reaching trajectory lands, s (see below).
constexpr double kReplanBeforeLandS = 0.3;
// The arm is on the trajectory sent when its state is this near it, rad
// (ephor-arm refuses a trajectory starting more than 0.05 rad off).
constexpr double kOnTrackRad = 0.02;
// A prediction whose reference time is more than this after now is not
// planned from, s: its poses are the capture times of frames already taken.
constexpr double kMaxPredictionAheadS = 1.0;
}  // namespace

PlannerTask::PlannerTask(const RamboCell& cell, const PlannerTaskOptions& options, int64_t run_id)
    : cell_(cell),
      options_(options),
      planner_(cell, options.tagging),
      arm_(cell.tool_length_mm),
      run_id_(run_id),
      tagged_(static_cast<std::size_t>(options.diodes), false) {}

bool PlannerTask::on_prediction(const rambo_prediction_t& m, std::string* why) {
  if (!m.fitted) return true;
  const std::optional<FittedMotion> f =
      motion_from_message(m, static_cast<double>(m.ref_utime) * 1e-6, why);
  if (!f) {
    ++bad_;
    return false;
  }
  motion_ = *f;
  motion_utime_ = m.ref_utime;
  return true;
}

bool PlannerTask::on_indicator(const rambo_indicator_t& m) {
  const int diodes = options_.diodes;
  if (m.num_diodes != diodes || static_cast<int>(m.tagged.size()) != diodes) {
    ++bad_;
    return false;
  }
  for (int i = 0; i < diodes; ++i)
    tagged_[static_cast<std::size_t>(i)] = m.tagged[static_cast<std::size_t>(i)];
  return true;
}

void PlannerTask::on_arm_state(const arm_state_t& m) {
  arm::Joints q;
  arm::Joints qd;
  for (int j = 0; j < 6; ++j) q[j] = m.q[j], qd[j] = m.qd[j];
  if (!q.allFinite() || !qd.allFinite()) return;
  q_now_ = q;
  qd_now_ = qd;
  state_utime_ = m.utime;
}

PlannerTask::Period PlannerTask::period(const std::function<int64_t()>& clock) {
  Period out;
  rambo_plan_t& plan = out.plan;
  plan = rambo_plan_t{};
  std::optional<arm::Joints> goal, look_goal;
  int64_t source_utime = 0;
  {
    const int64_t now = clock();
    plan.utime = now;
    plan.current_task = -1;
    // The prediction's age, s (in double: any utime a message carries).
    const double age_s = (static_cast<double>(now) - static_cast<double>(motion_utime_)) * 1e-6;
    if (!motion_ || !q_now_) {
      plan.status = "waiting for a prediction and the arm";
    } else if (age_s < -kMaxPredictionAheadS) {
      // Planning from it would extrapolate the motion back across the gap
      // (a prediction stamped 1700 years ahead: fuzz target rambo_planner).
      plan.status = "prediction stamped in the future (clocks apart?)";
    } else if (age_s > (motion_->polynomial ? options_.max_prediction_age_s
                                            : options_.max_rigid_prediction_age_s)) {
      plan.status = "prediction too old";
      // The camera is on the tool: after a reach that lost the target (a
      // wrong pose, or the tumble turning it away) no frame shows it again
      // while the arm waits where it is. Once per loss, back to the start
      // pose, whose view holds the whole target (RamboCell), when no
      // trajectory is running.
      if (!looking_ && now >= trajectory_end_utime_ &&
          (*q_now_ - cell_.start_joints).cwiseAbs().maxCoeff() > options_.arrive_rad) {
        looking_ = true;
        look_goal = cell_.start_joints;
        plan.status = "prediction too old: back to the viewing pose";
        trajectory_task_ = -2;
      }
    } else {
      looking_ = false;
      const TaggingStep s =
          planner_.step(static_cast<double>(now) * 1e-6, *motion_, tagged_, *q_now_);
      plan.status = s.status;
      plan.current_task = s.task;
      plan.order = s.order;
      plan.greedy_trajectories = s.greedy_trajectories;
      plan.exhaustive_trajectories = s.exhaustive_trajectories;
      plan.dp_trajectories = s.dp_trajectories;
      plan.order_total_s = std::isfinite(s.order_total_s) ? s.order_total_s : -1.0;
      goal = s.goal_q;
      source_utime = motion_utime_;
      if (s.reordered && s.order != logged_order_) {
        logged_order_ = s.order;
        std::string order;
        for (int i : s.order) order += " " + cell_.diodes[static_cast<std::size_t>(i)].name;
        spdlog::info(
            "order:{}; reaching trajectories computed: greedy {}, exhaustive {}, "
            "DP {}",
            order, s.greedy_trajectories, s.exhaustive_trajectories, s.dp_trajectories);
      }
    }
    if (plan.current_task != last_task_ || plan.status != last_status_) {
      spdlog::info("{}", plan.status);
      last_task_ = plan.current_task;
      last_status_ = plan.status;
    }
  }
  plan.num_tasks = static_cast<int32_t>(plan.order.size());
  // Reaching trajectories: one per diode, a new one only when the last has
  // ended (its hold over) and the diode is still open.
  std::optional<TaggingTrajectory> reaching;
  if (goal && options_.reach_trajectory) {
    const int64_t now = clock();
    // While the arm is on a trajectory to this diode (reaching or holding),
    // each newer prediction re-plans it (section 8: "the reaching trajectory
    // ... should be recomputed based on the new goal trajectory, and the
    // present joint trajectory, which may itself be a reaching trajectory"):
    // the new one leaves the trajectory being executed where the arm will be
    // on it when the goal arrives, in position and velocity.
    // Not in the last kReplanBeforeLandS before landing: the arm is then
    // near the goal trajectory anyway, and fast, so the new start would be
    // furthest from where the arm really is (the arm refuses a start more
    // than 0.05 rad off); it re-plans again once on the goal point.
    const bool on_it =
        plan.current_task == trajectory_task_ && sent_trajectory_ && now < trajectory_end_utime_;
    const bool landing = now < trajectory_land_utime_ &&
                         now > trajectory_land_utime_ - std::llround(kReplanBeforeLandS * 1e6);
    if (on_it && (motion_utime_ == trajectory_motion_utime_ || landing)) {
      goal.reset();  // the arm is on it
    } else {
      std::string why;
      // Starts where the arm will be when it gets it: the state extrapolated
      // to now + the relay's latency (or the running trajectory then).
      const double t0_s = static_cast<double>(now) * 1e-6 + kLatencyS;
      const double ahead_s = t0_s - static_cast<double>(state_utime_) * 1e-6;
      const arm::Joints q0 = *q_now_ + *qd_now_ * std::clamp(ahead_s, 0.0, 0.2);
      // Only from the trajectory the arm is really on: a refused one (the
      // arm checks the start within 0.05 rad) is not run, and re-planning
      // from it would drift further from the arm at every step (seen: 138 of
      // 167 refused, starts 0.05-0.33 rad off, the arm standing still
      // meanwhile).
      const bool from_running =
          on_it && (sent_trajectory_->at(t0_s).q - q0).cwiseAbs().maxCoeff() < kOnTrackRad;
      // Still reaching but off the sent trajectory (the arm started it late,
      // or refused it): no re-plan, as before section 8's was done here; the
      // arm's state extrapolated while it is fast would start too far from it.
      const bool reaching_off_track = on_it && !from_running && now < trajectory_land_utime_;
      if (!reaching_off_track)
        reaching = planner_.reaching_trajectory(plan.current_task, t0_s, *motion_, q0, *qd_now_,
                                                &why, options_.limit_fraction,
                                                from_running ? &*sent_trajectory_ : nullptr);
      if (!reaching && on_it) {
        // No better one from here: the arm stays on the one it has.
        trajectory_motion_utime_ = motion_utime_;
        goal.reset();
      }
      if (reaching) {
        if (from_running) ++replans_;
        sent_trajectory_ = reaching;
        trajectory_task_ = plan.current_task;
        trajectory_end_utime_ = std::llround(reaching->end_s() * 1e6);
        trajectory_land_utime_ = std::llround(reaching->t_land_s * 1e6);
        trajectory_motion_utime_ = motion_utime_;
        spdlog::info(
            "{}reaching trajectory to diode {}: lands in {:.2f} s{} ({} durations tried), "
            "then {:.1f} s on the goal point",
            on_it ? "re-planned " : "",
            cell_.diodes[static_cast<std::size_t>(plan.current_task)].name,
            reaching->t_land_s - reaching->t0_s,
            reaching->via_intermediate_goal ? " via a safe intermediate goal" : "",
            reaching->durations_tried, reaching->hold_end_s - reaching->t_land_s);
      } else if (goal) {
        // The point-to-point goal below instead.
        if (++trajectory_failures_ % 10 == 1)
          spdlog::warn("no reaching trajectory to diode {} ({}): a joint goal instead",
                       plan.current_task, why);
      }
    }
  }
  // Each goal makes the arm plan anew from rest: while it is still on its
  // way, a goal that has barely moved is not sent again (it would only slow
  // the reach down); once the arm is there, the goal is refreshed every
  // period so that the laser follows the diode.
  if (goal && !reaching) {
    const bool arrived =
        sent_goal_ && q_now_ && (*q_now_ - *sent_goal_).cwiseAbs().maxCoeff() < options_.arrive_rad;
    const bool moved =
        !sent_goal_ || (*goal - *sent_goal_).cwiseAbs().maxCoeff() > options_.resend_rad;
    if (plan.current_task != sent_task_ || arrived || moved) {
      sent_goal_ = goal;
      sent_task_ = plan.current_task;
    } else {
      goal.reset();
    }
  }
  if (look_goal) {
    goal = look_goal;
    sent_goal_ = goal;
    sent_task_ = -1;
  }
  if (goal) {
    arm_goal_t g{};
    g.utime = clock();
    g.goal_id = run_id_ + goals_;
    g.kind = arm_goal_t::KIND_JOINTS;
    for (int j = 0; j < 6; ++j) g.joints_rad[j] = (*goal)[j];
    if (reaching) {
      g.kind = arm_goal_t::KIND_TRAJECTORY;
      for (std::size_t k = 0; k < reaching->samples.size(); ++k) {
        const JointSample& js = reaching->samples[k];
        g.traj_t_s.push_back(static_cast<float>(reaching->dt_s * static_cast<double>(k)));
        g.traj_q_rad.emplace_back(js.q.data(), js.q.data() + 6);
        g.traj_qd_rad_s.emplace_back(js.qd.data(), js.qd.data() + 6);
      }
      g.num_points = static_cast<int32_t>(g.traj_t_s.size());
      const arm::Joints& last = reaching->samples.back().q;
      for (int j = 0; j < 6; ++j) g.joints_rad[j] = last[j];
      ++trajectories_;
    }
    g.max_speed_mm_s = 0.0f;
    g.source_frame_utime = source_utime;
    g.target_object = plan.current_task;
    out.goal = std::move(g);
    ++goals_;
  }
  plan.goals_sent = goals_;
  return out;
}

}  // namespace ephor::rambo
