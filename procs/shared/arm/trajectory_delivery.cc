#include "procs/shared/arm/trajectory_delivery.h"

#include <spdlog/fmt/fmt.h>

namespace ephor::arm {

void TrajectoryDelivery::sent(int64_t seq, const Joints& first_q, bool stop, int64_t now_us) {
  pending_ = true;
  stop_ = stop;
  seq_ = seq;
  first_q_ = first_q;
  sent_us_ = now_us;
  why_.clear();
}

void TrajectoryDelivery::resent(int64_t now_us) {
  sent_us_ = now_us;
  ++resends_;
}

TrajectoryDelivery::Action TrajectoryDelivery::check(const ServoState& servo, int64_t now_us) {
  if (!pending_) return Action::kNone;
  if (servo.trajectory_seq == seq_) {
    pending_ = false;  // taken up
    return Action::kNone;
  }
  if (now_us - sent_us_ < static_cast<int64_t>(config_.resend_after_s * 1e6)) return Action::kNone;
  if (stop_) return Action::kReplanStop;
  int worst = 0;
  const double away = (servo.q - first_q_).cwiseAbs().maxCoeff(&worst);
  if (away <= config_.start_tolerance_rad) return Action::kResend;
  pending_ = false;
  why_ = fmt::format(
      "trajectory {} was not taken up by the servo within {:.0f} ms (lost?) and joint {} has "
      "since moved {:.3f} rad from its start: planned again on the next goal",
      seq_, (now_us - sent_us_) / 1e3, worst + 1, away);
  return Action::kGiveUp;
}

}  // namespace ephor::arm
