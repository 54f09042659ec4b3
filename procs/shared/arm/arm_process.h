#pragma once
// ArmProcess: ephor-arm's handlers and tasks (the arm server; main.cc says
// what the process does): ARM_CMD queued by on_command and validated, planned
// and sent by command_job (task "command"), ESTOP acted on at once by
// on_estop, ARM_SERVO by on_servo, and ARM_STATE published by state_job
// (task "state", every 10 ms).
//
// Out of main.cc (issue 18) so that the fuzz target arm_process
// (arm_process_fuzz.cc) runs the process's own code on any interleaving of
// messages and task releases: what it publishes goes through ArmOutputs
// (main.cc: the bus and the task runtime) and it reads the time through
// ArmClock (main.cc: ephor::mono_us and ephor::wall_us; the fuzz target: a
// fake clock). main.cc keeps the flags, the bus subscriptions and the
// TaskRuntime registration.
//
// Threading as in the process: the handlers run on the bus thread, the jobs
// on their task threads; every method may be called from any thread.

#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <string>

#include "common/arm/puma560.h"
#include "common/calibration/field_calibration.h"
#include "common/geometry/overhead_camera.h"
#include "common/geometry/workcell.h"
#include "common/motion/motion_planner.h"
#include "ephor/arm_ack_t.hpp"
#include "ephor/arm_cmd_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/estop_t.hpp"
#include "ephor/joint_state_t.hpp"
#include "ephor/joint_trajectory_t.hpp"
#include "procs/shared/arm/arm_command.h"
#include "procs/shared/arm/command_ledger.h"
#include "procs/shared/arm/command_validator.h"
#include "procs/shared/arm/execution_monitor.h"
#include "procs/shared/arm/safety_gate.h"
#include "procs/shared/arm/trajectory_delivery.h"

namespace ephor::arm {

struct ArmProcessOptions {
  double max_speed_mm_s = 300.0;
  double max_age_ms = 500.0;
  std::string accept_from = "comm";
  double servo_silence_ms = 250.0;  // refuse commands when the servo has been quiet this long
  double replan_tolerance_rad = 0.02;
  double comm_timeout_ms = 1000.0;  // stop a motion when comm is silent this long; 0 = never
  // OMPL's time budget for one joint-space plan, s (no flag: the fuzz target
  // shortens it).
  double planner_time_budget_s = JointPlannerConfig{}.time_budget_s;
};

// Where ArmProcess's messages go. main.cc: the bus (ephor::Bus::publish,
// which fills in each message's header) and the task runtime. Each publish_*
// returns false when the message was not sent (Bus::publish's result).
class ArmOutputs {
 public:
  virtual ~ArmOutputs() = default;
  virtual bool publish_state(arm_state_t& m) = 0;  // ARM_STATE
  virtual bool publish_ack(arm_ack_t& m) = 0;      // ARM_ACK
  // ARM_TRAJECTORY. `stop`: a controlled stop (an ESTOP, comm silent, or a
  // lost stop planned again), else a motion (or a lost one sent again).
  virtual bool publish_trajectory(joint_trajectory_t& m, bool stop) = 0;
  // An ARM_CMD was queued: release the task "command" (command_job).
  virtual void command_queued() = 0;
};

// The clocks ArmProcess reads, us: monotonic (periods, silences, deadlines)
// and wall (message utime, command age, the ledger's start).
struct ArmClock {
  std::function<int64_t()> mono_us;
  std::function<int64_t()> wall_us;
  static ArmClock system();  // ephor::mono_us and ephor::wall_us
};

class ArmProcess {
 public:
  ArmProcess(ArmOutputs& outputs, const geometry::Workcell& cell,
             calibration::FieldCalibration calibration, const geometry::OverheadCamera& camera,
             ArmProcessOptions options, ArmClock clock = ArmClock::system());

  static MotionPlannerConfig planner_config(const geometry::Workcell& cell,
                                            const ArmProcessOptions& o);

  // Bus thread: queues the command (from options.accept_from only) and
  // releases command_job.
  void on_command(const arm_cmd_t& m);
  // Bus thread: acted on at once, not queued behind commands being planned.
  void on_estop(const estop_t& m);
  // Bus thread.
  void on_servo(const joint_state_t& m);
  // Task "command": validates, plans and sends every queued command in order.
  void command_job();
  // Task "state", every 10 ms.
  void state_job();

  void log_summary() const;

  const Puma560& arm() const { return arm_; }

 private:
  calibration::Plane nearest_plane(double z_mm) const;
  int plane_by_height(double z_mm) const;

  // Caller holds mutex_ (all below but handle_command).
  void publish_ack(const ArmAck& ack, int64_t cmd_utime);
  void finish_if(const std::optional<ArmAck>& ack);
  void reject(const arm_cmd_t& m, std::string reason);
  // FAILED, not REJECTED: the command may have been executed (by the arm's
  // run before a restart), which REJECTED would deny.
  void fail_unknown(const arm_cmd_t& m, std::string reason);
  void handle_command(const arm_cmd_t& m);
  // Brings the arm to rest now and fails the motion in progress.
  void stop_motion(const std::string& why);
  // Sends the last trajectory again when the servo has not taken it up
  // (TrajectoryDelivery: a lost datagram).
  void deliver();
  // Returns the trajectory's seq. `stop`: a controlled stop (sent again from
  // where the arm is if lost), else a motion.
  int64_t publish_trajectory(const Trajectory& trajectory, bool stop);
  void send(const arm_cmd_t& m, const Validation& v, const MotionPlan& plan);

  ArmOutputs& outputs_;
  ArmClock clock_;
  geometry::Workcell cell_;
  ArmProcessOptions options_;
  Puma560 arm_;
  CommandValidator validator_;
  calibration::FieldCalibration calibration_;
  MotionPlanner planner_;

  std::mutex queue_mutex_;
  std::deque<arm_cmd_t> queue_;

  std::mutex mutex_;  // everything below
  std::optional<ServoState> servo_;
  int64_t servo_mono_us_ = 0;
  CommandLedger ledger_;
  ExecutionMonitor monitor_;
  SafetyGate gate_;
  int64_t executing_cmd_utime_ = 0;
  int64_t next_trajectory_seq_;
  TrajectoryDelivery delivery_;
  joint_trajectory_t last_trajectory_;

  std::atomic<int64_t> accepted_{0}, rejected_{0}, repeats_{0}, foreign_{0}, bad_servo_{0},
      from_before_start_{0}, resends_{0};
};

}  // namespace ephor::arm
