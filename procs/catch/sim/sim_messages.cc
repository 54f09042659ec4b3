#include "procs/catch/sim/sim_messages.h"

#include <cmath>
#include <string>
#include <utility>

#include <spdlog/spdlog.h>

#include "common/arm/servo_messages.h"

namespace ephor::catching {

catch_truth_t to_truth(const CatchScenario& scenario, const BoardWorld& world,
                       const BallSequence& balls, const CatchCell& cell, const arm::Joints& q) {
  catch_truth_t m{};
  const BallState s = world.state();
  switch (balls.phase()) {
    case BallSequence::Phase::kWaiting:
      m.phase = catch_truth_t::PHASE_WAITING;
      break;
    case BallSequence::Phase::kRolling:
      m.phase = catch_truth_t::PHASE_ROLLING;
      break;
    case BallSequence::Phase::kFlying:
      m.phase = catch_truth_t::PHASE_FLYING;
      break;
    case BallSequence::Phase::kDone:
      m.phase = catch_truth_t::PHASE_DONE;
      break;
  }
  m.ball = balls.ball();
  const Eigen::Vector3d w = scenario.board_to_world() * s.position_b_mm;
  for (int k = 0; k < 3; ++k) {
    m.ball_b_mm[k] = s.position_b_mm[k];
    m.ball_w_mm[k] = w[k];
  }
  m.ball_velocity_b_mm_s[0] = s.velocity_b_mm_s.x();
  m.ball_velocity_b_mm_s[1] = s.velocity_b_mm_s.y();
  m.ball_px[0] = m.ball_px[1] = std::nan("");
  if (const auto& e = balls.expected_exit()) m.exit_x_b_mm = e->x_b_mm;
  const Eigen::Vector3d cup = cell.cup_w_mm(q);
  for (int k = 0; k < 3; ++k) m.cup_w_mm[k] = cup[k];
  m.incline_deg = scenario.placement.incline_rad * 180.0 / M_PI;
  const Eigen::Matrix3d r = scenario.board_to_camera.linear();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m.board_to_camera_r[3 * i + j] = r(i, j);
    m.board_to_camera_t_mm[i] = scenario.board_to_camera.translation()[i];
  }
  m.balls_done = balls.done();
  m.caught = balls.caught();
  m.oracle_reachable = balls.oracle_reachable();
  m.last_ball = -1;
  if (const auto& last = balls.last()) {
    m.last_ball = last->ball;
    m.last_caught = last->caught;
    m.last_oracle_reachable = last->oracle_reachable;
    m.last_reason = last->reason;
  }
  return m;
}

CatchSimProcess::CatchSimProcess(CatchScenario s, const geometry::Workcell& c, int ball_count,
                                 double gap_s, double first_release_s)
    : scenario(std::move(s)),
      cell(c),
      catch_cell(scenario, cell),
      world(scenario),
      servo(catch_cell.puma().limits(), catch_cell.park_joints()),
      balls(scenario, ball_count, gap_s, first_release_s) {}

bool CatchSimProcess::on_trajectory(const joint_trajectory_t& m) {
  std::string why;
  auto t = sim::to_trajectory(m, why);
  if (!t) {
    ++trajectories_refused;
    spdlog::warn("ARM_TRAJECTORY seq {} ignored: {} ({} ignored so far)", m.seq, why,
                 trajectories_refused.load());
    return false;
  }
  std::lock_guard<std::mutex> lock(mutex);
  pending = std::move(*t);
  return true;
}

void CatchSimProcess::step() {
  if (pending) {
    servo.follow(*pending);
    pending.reset();
  }
  servo.step(kSimStepS);
  world.step(kSimStepS);
  clock_s += kSimStepS;
  balls.step(world, catch_cell, servo.state().q, world.time_s(),
             servo.state().qd.cwiseAbs().maxCoeff() < 0.01);
}

void CatchSimProcess::advance_to(double now_s) {
  if (now_s - clock_s > kSimMaxLagS) {
    ++physics_skips;
    spdlog::warn("physics {:.3f} s behind the clock; skipping ahead", now_s - clock_s);
    clock_s = now_s - kSimStepS;
  }
  while (clock_s + kSimStepS <= now_s) step();
}

joint_state_t CatchSimProcess::servo_message() const {
  return sim::to_joint_state(servo.state(), utime_of(clock_s));
}

catch_truth_t CatchSimProcess::truth() const {
  catch_truth_t m = to_truth(scenario, world, balls, catch_cell, servo.state().q);
  if (const auto& e = balls.expected_exit()) m.exit_utime = utime_of(e->time_s);
  m.utime = utime_of(clock_s);
  return m;
}

}  // namespace ephor::catching
