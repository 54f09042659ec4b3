#include "procs/shared/comm/goal_relay.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

namespace ephor::comm {
namespace {
constexpr int32_t kMaxSeqMoves = 2;  // fresh seqs per goal after a goal_id mismatch
}  // namespace

const char* to_string(Outcome outcome) {
  switch (outcome) {
    case Outcome::kDone:
      return "DONE";
    case Outcome::kRejected:
      return "REJECTED";
    case Outcome::kFailed:
      return "FAILED";
    case Outcome::kTimeout:
      return "TIMEOUT";
  }
  return "?";
}

const char* to_string(AckStatus status) {
  switch (status) {
    case AckStatus::kAccepted:
      return "ACCEPTED";
    case AckStatus::kDone:
      return "DONE";
    case AckStatus::kRejected:
      return "REJECTED";
    case AckStatus::kFailed:
      return "FAILED";
  }
  return "?";
}

std::optional<std::string> goal_problem(const Goal& goal) {
  if (goal.goal_id < 0) return fmt::format("goal_id {} is negative", goal.goal_id);
  if (goal.kind < 0 || goal.kind > 3)
    return fmt::format(
        "kind {} is none of KIND_IMAGE (0), KIND_POSE (1), KIND_JOINTS (2), KIND_TRAJECTORY (3)",
        static_cast<int>(goal.kind));
  if (goal.kind == 3) {
    if (goal.traj_t_s.size() < 2 || goal.traj_q_rad.size() != goal.traj_t_s.size() ||
        goal.traj_qd_rad_s.size() != goal.traj_t_s.size())
      return fmt::format("trajectory of {} times, {} positions and {} velocities (want >= 2 each)",
                         goal.traj_t_s.size(), goal.traj_q_rad.size(), goal.traj_qd_rad_s.size());
    const auto finite = [](const std::array<double, 6>& a) {
      return std::all_of(a.begin(), a.end(), [](double x) { return std::isfinite(x); });
    };
    for (std::size_t k = 0; k < goal.traj_t_s.size(); ++k)
      if (!std::isfinite(goal.traj_t_s[k]) || !finite(goal.traj_q_rad[k]) ||
          !finite(goal.traj_qd_rad_s[k]))
        return fmt::format("trajectory point {} is not finite", k);
  }
  if (goal.kind == 0 && goal.plane != static_cast<int8_t>(Plane::kElevation) &&
      goal.plane != static_cast<int8_t>(Plane::kObject))
    return fmt::format("plane {} is neither PLANE_ELEVATION (0) nor PLANE_OBJECT (1)",
                       static_cast<int>(goal.plane));
  if (goal.kind == 0 && (!std::isfinite(goal.u) || !std::isfinite(goal.v)))
    return fmt::format("target (u, v) = ({}, {}) px is not finite", goal.u, goal.v);
  if (goal.kind == 1 && !std::all_of(goal.position_mm.begin(), goal.position_mm.end(),
                                     [](double x) { return std::isfinite(x); }))
    return fmt::format("position ({}, {}, {}) mm is not finite", goal.position_mm[0],
                       goal.position_mm[1], goal.position_mm[2]);
  if (goal.kind == 2 && !std::all_of(goal.joints_rad.begin(), goal.joints_rad.end(),
                                     [](double x) { return std::isfinite(x); }))
    return "joint target is not finite";
  if (!std::isfinite(goal.theta_rad))
    return fmt::format("theta_rad = {} is not finite", goal.theta_rad);
  if (!std::isfinite(goal.max_speed_mm_s) || goal.max_speed_mm_s < 0.0f)
    return fmt::format("max_speed_mm_s = {} is not a finite speed >= 0", goal.max_speed_mm_s);
  return std::nullopt;
}

GoalRelay::GoalRelay(RelayOptions options) : options_(options) {
  if (options_.retry_interval_us <= 0)
    throw std::invalid_argument(
        fmt::format("retry interval must be > 0 us, got {}", options_.retry_interval_us));
  if (options_.max_attempts < 1)
    throw std::invalid_argument(
        fmt::format("max attempts must be >= 1, got {}", options_.max_attempts));
  if (options_.poll_interval_us <= 0)
    throw std::invalid_argument(
        fmt::format("poll interval must be > 0 us, got {}", options_.poll_interval_us));
  if (!std::isfinite(options_.done_margin_factor) || options_.done_margin_factor < 0.0)
    throw std::invalid_argument(fmt::format("done margin factor must be finite and >= 0, got {}",
                                            options_.done_margin_factor));
  if (options_.done_margin_us < 0)
    throw std::invalid_argument(
        fmt::format("done margin must be >= 0 us, got {}", options_.done_margin_us));
  if (!std::isfinite(options_.max_planned_duration_s) || options_.max_planned_duration_s <= 0.0f)
    throw std::invalid_argument(fmt::format("max planned duration must be finite and > 0 s, got {}",
                                            options_.max_planned_duration_s));
  if (options_.finished_memory < 1)
    throw std::invalid_argument(
        fmt::format("finished memory must be >= 1, got {}", options_.finished_memory));
}

void GoalRelay::submit(const Goal& goal, int64_t now_us) {
  ++counters_.goals_received;
  if (auto problem = goal_problem(goal)) {
    ++counters_.goals_invalid;
    ++counters_.rejected;
    MotionDone d;
    d.goal_id = goal.goal_id;
    d.status = Outcome::kRejected;
    d.reason = "invalid goal: " + *problem;
    done_out_.push_back(std::move(d));
    return;
  }
  if (is_duplicate(goal)) {
    ++counters_.goals_duplicate;
    return;
  }
  if (pending_) ++counters_.goals_superseded;
  pending_ = Pending{goal, now_us};
}

bool GoalRelay::is_duplicate(const Goal& goal) const {
  auto same = [&goal](const Goal& g) {
    return g.goal_id == goal.goal_id && g.planned_utime == goal.planned_utime;
  };
  if (pending_ && same(pending_->goal)) return true;
  if (in_flight_ && same(in_flight_->goal)) return true;
  return std::any_of(finished_.begin(), finished_.end(), [&goal](const Finished& f) {
    return f.goal_id == goal.goal_id && f.planned_utime == goal.planned_utime;
  });
}

void GoalRelay::remember_finished(Finished f) {
  finished_.push_back(std::move(f));
  while (static_cast<int32_t>(finished_.size()) > options_.finished_memory) finished_.pop_front();
}

void GoalRelay::raise_next_seq(int64_t seen_seq) {
  // A seq no arm reaches (one a second for 10^11 years) is a corrupt message:
  // following it would overflow the next seq (found by fuzz_comm_goal_relay:
  // an ARM_STATE with executing_seq 2^63 - 1).
  if (seen_seq > kMaxSeq || seen_seq < 0) {
    ++counters_.implausible_seqs;
    return;
  }
  if (seen_seq >= next_seq_) next_seq_ = seen_seq + 1;
}

void GoalRelay::on_arm_progress(const ArmProgress& progress, int64_t /*now_us*/) {
  arm_heard_ = true;
  raise_next_seq(std::max(progress.executing_seq, progress.last_done_seq));
}

void GoalRelay::on_ack(const Ack& ack, int64_t now_us) {
  if (in_flight_ && ack.seq == in_flight_->seq) {
    InFlight& f = *in_flight_;
    if (ack.goal_id != f.goal.goal_id) {
      // The arm knows this seq as another goal's: it will never execute ours
      // under it. Move the goal to a fresh seq; step() sends it. An arm that
      // keeps answering with the wrong goal_id may be executing every seq, so
      // give up after a few moves rather than resend the goal forever.
      ++counters_.acks_unknown;
      ++counters_.seq_conflicts;
      raise_next_seq(ack.seq);
      if (++f.seq_moves > kMaxSeqMoves) {
        finish(Outcome::kFailed,
               fmt::format("the arm answered seq {} for goal {} instead of {} ({} times): acks do "
                           "not match commands, not resending",
                           ack.seq, ack.goal_id, f.goal.goal_id, f.seq_moves),
               now_us);
        return;
      }
      f.seq = next_seq_++;
      f.phase = Phase::kDelivering;
      f.attempts = 0;
      f.transmissions = 0;  // the fresh seq's first send is its transmission 1 (issue 18, fuzzing)
      f.last_sent_us = now_us - options_.retry_interval_us;  // due at once
      return;
    }
    switch (ack.status) {
      case AckStatus::kAccepted: {
        if (f.phase == Phase::kExecuting) {
          ++counters_.acks_duplicate;
          return;
        }
        float planned = ack.planned_duration_s;
        if (!std::isfinite(planned) || planned > options_.max_planned_duration_s)
          planned = options_.max_planned_duration_s;
        planned = std::max(planned, 0.0f);
        f.phase = Phase::kExecuting;
        f.done_deadline_us = now_us +
                             static_cast<int64_t>(static_cast<double>(planned) * 1e6 *
                                                  (1.0 + options_.done_margin_factor)) +
                             options_.done_margin_us;
        return;
      }
      case AckStatus::kDone:
        finish(Outcome::kDone, ack.reason, now_us);
        return;
      case AckStatus::kRejected:
        finish(Outcome::kRejected,
               ack.reason.empty() ? "rejected by the arm (no reason given)" : ack.reason, now_us);
        return;
      case AckStatus::kFailed:
        finish(Outcome::kFailed,
               ack.reason.empty() ? "failed on the arm (no reason given)" : ack.reason, now_us);
        return;
    }
    return;
  }
  for (Finished& f : finished_) {
    if (f.seq == ack.seq && f.goal_id == ack.goal_id) {
      on_finished_seq_ack(f, ack, now_us);
      return;
    }
  }
  ++counters_.acks_unknown;
  // An ack for a seq this relay never sent means the arm has seen that seq
  // (from an earlier comm): never reuse it.
  raise_next_seq(ack.seq);
}

void GoalRelay::on_finished_seq_ack(Finished& f, const Ack& ack, int64_t now_us) {
  const bool final_ack = ack.status != AckStatus::kAccepted;
  if (f.status == Outcome::kTimeout && final_ack && !f.late_reported) {
    f.late_reported = true;
    ++counters_.late_confirmations;
    late_out_.push_back(
        LateConfirmation{f.goal_id, f.seq, ack.status, ack.reason, now_us - f.finished_us});
    return;
  }
  ++counters_.acks_duplicate;
}

void GoalRelay::finish(Outcome status, std::string reason, int64_t now_us) {
  const InFlight& f = *in_flight_;
  MotionDone d;
  d.goal_id = f.goal.goal_id;
  d.seq = f.seq;
  d.status = status;
  d.reason = std::move(reason);
  d.attempts = f.attempts;
  d.round_trip_us = now_us - f.first_sent_us;
  done_out_.push_back(std::move(d));
  switch (status) {
    case Outcome::kDone:
      ++counters_.done;
      break;
    case Outcome::kRejected:
      ++counters_.rejected;
      break;
    case Outcome::kFailed:
      ++counters_.failed;
      break;
    case Outcome::kTimeout:
      ++counters_.timeouts;
      break;
  }
  remember_finished(Finished{f.seq, f.goal.goal_id, f.goal.planned_utime, status, now_us, false});
  in_flight_.reset();
}

void GoalRelay::transmit(RelayOutput& out, int64_t now_us, bool first) {
  InFlight& f = *in_flight_;
  const bool new_seq = f.transmissions == 0;  // also a goal moved to a fresh seq
  ++f.transmissions;
  if (f.phase == Phase::kDelivering) {
    ++f.attempts;
    if (new_seq) {
      ++counters_.commands_sent;
      if (first) f.first_sent_us = now_us;
    } else {
      ++counters_.retransmissions;
    }
  } else {
    ++counters_.polls;
  }
  f.last_sent_us = now_us;
  out.commands.push_back(Command{f.seq, f.goal, f.transmissions});
}

RelayOutput GoalRelay::step(int64_t now_us) {
  RelayOutput out;

  // A goal held because the arm was never heard must still end, so the
  // planner is not left waiting.
  const int64_t give_up_us = options_.max_attempts * options_.retry_interval_us;
  if (pending_ && !in_flight_ && options_.wait_for_arm_state && !arm_heard_ &&
      now_us - pending_->received_us >= give_up_us) {
    MotionDone d;
    d.goal_id = pending_->goal.goal_id;
    d.status = Outcome::kTimeout;
    d.reason = fmt::format("no arm state heard within {} ms: the arm's seq is unknown, not sent",
                           give_up_us / 1000);
    done_out_.push_back(std::move(d));
    ++counters_.timeouts;
    // seq 0: no ack can match it, but a republished copy is still a duplicate.
    remember_finished(Finished{0, pending_->goal.goal_id, pending_->goal.planned_utime,
                               Outcome::kTimeout, now_us, true});
    pending_.reset();
  }

  if (in_flight_) {
    InFlight& f = *in_flight_;
    if (f.phase == Phase::kDelivering) {
      if (now_us - f.last_sent_us >= options_.retry_interval_us) {
        if (f.attempts >= options_.max_attempts) {
          finish(Outcome::kTimeout,
                 fmt::format("no answer from the arm to {} sends over {} ms", f.attempts,
                             (now_us - f.first_sent_us) / 1000),
                 now_us);
        } else {
          transmit(out, now_us, false);
        }
      }
    } else if (now_us >= f.done_deadline_us) {
      finish(Outcome::kTimeout,
             fmt::format("accepted but no DONE/FAILED by the deadline ({} ms after the first send)",
                         (now_us - f.first_sent_us) / 1000),
             now_us);
    } else if (now_us - f.last_sent_us >= options_.poll_interval_us) {
      transmit(out, now_us, false);
    }
  }

  if (options_.preempt_in_flight && in_flight_ && pending_ &&
      in_flight_->phase == Phase::kExecuting) {
    finish(Outcome::kFailed, fmt::format("superseded by goal {}", pending_->goal.goal_id), now_us);
  }

  if (!in_flight_ && pending_ && (arm_heard_ || !options_.wait_for_arm_state)) {
    InFlight f;
    f.seq = next_seq_++;
    f.goal = pending_->goal;
    pending_.reset();
    in_flight_ = std::move(f);
    transmit(out, now_us, true);
  }

  out.done = std::move(done_out_);
  out.late = std::move(late_out_);
  done_out_.clear();
  late_out_.clear();
  return out;
}

}  // namespace ephor::comm
