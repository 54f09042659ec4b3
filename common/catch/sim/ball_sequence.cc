#include "common/catch/sim/ball_sequence.h"

#include <fmt/format.h>

namespace ephor::catching {

BallSequence::BallSequence(const CatchScenario& scenario, int balls, double gap_s,
                           double first_release_s, double max_arm_wait_s)
    : scenario_(scenario),
      judge_(scenario.board, scenario.placement),
      balls_(balls),
      gap_s_(gap_s),
      first_release_s_(first_release_s),
      max_arm_wait_s_(max_arm_wait_s) {}

double BallSequence::finished_for_s(double now_s) const {
  return phase_ == Phase::kDone ? now_s - phase_since_s_ : 0.0;
}

void BallSequence::step(BoardWorld& world, const CatchCell& cell, const arm::Joints& q,
                        double now_s, bool arm_still) {
  auto finish = [&](bool caught, std::string reason) {
    ++done_;
    if (caught) ++caught_;
    if (current_reachable_) ++oracle_reachable_;
    last_ = Result{ball_, caught, current_reachable_, std::move(reason)};
    ++ball_;
    phase_since_s_ = now_s;
    phase_ = balls_ > 0 && done_ >= balls_ ? Phase::kDone : Phase::kWaiting;
  };
  switch (phase_) {
    case Phase::kWaiting:
      if (now_s - phase_since_s_ < gap_s_ || now_s < first_release_s_) return;
      if (!arm_still && now_s - phase_since_s_ < gap_s_ + max_arm_wait_s_) return;
      world.release(scenario_.release(ball_));
      expected_exit_ = world.predict_exit().exit;
      current_reachable_ = false;
      if (expected_exit_) {
        const auto c = judge_.catch_plane_crossing(*expected_exit_);
        current_reachable_ = cell.move_time_from_ready_s(c.point_w_mm) <= c.time_s - now_s;
      }
      phase_ = Phase::kRolling;
      phase_since_s_ = now_s;
      return;
    case Phase::kRolling:
      if (world.stalled()) return finish(false, CatchJudge::stalled().reason);
      if (!world.exit()) return;
      crossing_ = judge_.catch_plane_crossing(*world.exit());
      phase_ = Phase::kFlying;
      return;
    case Phase::kFlying: {
      // Judged where the ball falls through the cup's opening: once it is
      // below the catch plane the cup had its chance.
      if (now_s < crossing_->time_s) return;
      const Eigen::Vector3d cup = cell.cup_w_mm(q);
      const CatchVerdict v = judge_.judge(*world.exit(), cup);
      finish(v.caught, v.reason);
      last_->ball_w_mm = v.ball_w_mm;
      last_->cup_w_mm = cup;
      return;
    }
    case Phase::kDone:
      return;
  }
}

}  // namespace ephor::catching
