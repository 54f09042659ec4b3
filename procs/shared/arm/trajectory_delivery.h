#pragma once
// TrajectoryDelivery: makes sure the servo takes up the trajectory the arm
// last sent (ARM_TRAJECTORY is one multicast datagram: under packet loss it
// can vanish, and before this a lost motion waited for comm's deadline, a
// lost controlled stop left the arm moving).
//
// The servo reports the seq it follows in every joint state and ignores a
// repeat of that seq, so an unanswered trajectory is sent again:
// - a motion, as it was, while the arm is still where the trajectory begins
//   (within start_tolerance_rad); once the arm has moved away (it was still
//   following the motion before), it can no longer be sent as planned: the
//   motion is given up, failed with the reason, and comm's goal is planned
//   again;
// - a stop, planned again from where the arm is now (a new seq), until one
//   is taken.
//
// Pure logic fed with servo states and the monotonic clock (us); not thread
// safe (one owner).

#include <cstdint>
#include <optional>
#include <string>

#include "common/arm/puma560.h"
#include "procs/shared/arm/arm_command.h"

namespace ephor::arm {

struct TrajectoryDeliveryConfig {
  // The servo reports every 4-10 ms; a trajectory not reported after this
  // long was lost (or its report was), s.
  double resend_after_s = 0.1;
  // A motion is sent again only while every joint is this close to its first
  // point (the servo's own start check allows 0.05 rad), rad.
  double start_tolerance_rad = 0.02;
};

class TrajectoryDelivery {
 public:
  enum class Action { kNone, kResend, kReplanStop, kGiveUp };

  explicit TrajectoryDelivery(TrajectoryDeliveryConfig config = {}) : config_(config) {}

  // A trajectory was published at now_us: a motion beginning at first_q, or
  // a controlled stop.
  void sent(int64_t seq, const Joints& first_q, bool stop, int64_t now_us);
  // What to do on this servo state (or tick with the newest one): nothing
  // (taken up, or not yet due), send it again, plan the stop again, or give
  // the motion up (why() says why). After kResend / kReplanStop the caller
  // sends and calls resent() / sent().
  Action check(const ServoState& servo, int64_t now_us);
  void resent(int64_t now_us);

  bool pending() const { return pending_; }
  int64_t seq() const { return seq_; }
  const std::string& why() const { return why_; }
  int64_t resends() const { return resends_; }

 private:
  TrajectoryDeliveryConfig config_;
  bool pending_ = false;
  bool stop_ = false;
  int64_t seq_ = 0;
  Joints first_q_ = Joints::Zero();
  int64_t sent_us_ = 0;
  int64_t resends_ = 0;
  std::string why_;
};

}  // namespace ephor::arm
