#pragma once
// SaveCyclePlanner: the save cycle shared by the planners of paper 003,
// section 3.4, as a state machine driven by planning jobs and motion_done
// events:
//
//   choose --(intercept accepted)--> moving (elevation plane, facing centre)
//   moving --done--> verifying: target still there and still leaving? intercept
//            re-planned from where the arm really is (the arm may be slower
//            than hoped: far off -> move again); no other sheep under the arm
//   verifying --> lowering (object plane over the target) --> turning: wait for
//            the touch that turns the sheep toward the centre, correcting the
//            tool in the object plane if the sheep's path drifts
//   turning --(target turned / gone / passed / waited too long)--> raising
//   raising --done--> choose again (or park, for the single-sheep planner)
//   choose --(nobody needs saving)--> parking at the lower-right corner
//
// A failed or timed-out goal sends the cycle back to choose (after raising
// when the tool may be down). Subclasses decide which sheep to save and
// where to meet it.

#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "procs/shepherd/planner/arm_configuration.h"
#include "procs/shepherd/planner/field_rules.h"
#include "procs/shepherd/planner/intercept_solver.h"
#include "procs/shepherd/planner/planner.h"

namespace ephor::planner {

// A sheep chosen to save and where to meet it.
struct SavePlan {
  int target = -1;
  Intercept intercept;
  bool ignores_other_sheep = false;  // chosen as a last resort despite another sheep's path
};

class SaveCyclePlanner : public Planner {
 public:
  explicit SaveCyclePlanner(const PlannerConfig& config);

  std::optional<Goal> plan(const Scene& scene) override;
  bool on_motion_done(int64_t goal_id, bool succeeded) override;
  PlannerStatus status() const override { return status_; }

  enum class Phase {
    kChoosing,
    kMoving,
    kVerifying,
    kLowering,
    kTurning,
    kCorrecting,
    kRaising,
    kParking,
    kParked,
    kHolding
  };
  Phase phase() const { return phase_; }
  static const char* phase_name(Phase phase);

 protected:
  // Step 1 and 2: which sheep to save now and the accepted intercept.
  // `candidates` is set to the number of sheep that need saving. nullopt
  // with candidates == 0: nobody needs saving (park); otherwise every
  // intercept was rejected (hold and try again next job).
  virtual std::optional<SavePlan> choose(const Scene& scene, int* candidates) = 0;
  // Step 3's re-plan once the arm is over the intercept: where to lower.
  virtual std::optional<Intercept> replan_at_intercept(const Scene& scene, const Sheep& target);
  // Whether step 3 re-checks for other sheep under the arm.
  virtual bool checks_other_sheep() const { return true; }
  // Whether to park after every save (the single-sheep planner does).
  virtual bool parks_after_save() const { return false; }

  const FieldRules& rules() const { return rules_; }
  // Indices into scene.sheep of the sheep needing saving, soonest to leave
  // first, without those saved less than resave_cooldown_s ago or saved while
  // hidden and not seen since.
  std::vector<int> save_candidates(const Scene& scene);
  const PlannerConfig& config() const { return rules_.config(); }
  // Delay between reaching the intercept in the elevation plane and the
  // tool being down, plus the overheads of the move and the lowering goals.
  double lowering_delay_s(const ArmModel& arm) const;
  // Extra time, s, for an elevation-plane move of the tool to (x, y) facing
  // the centre, when the arm's joints are known: ArmModel::configuration_switch_s
  // when the point is outside the current configuration's region, else
  // ArmModel::column_detour_s when the straight line passes the column, else 0.
  double switch_time_s(const ArmModel& arm, double x_mm, double y_mm) const;
  // True when the straight tool path from (ax, ay) to (x, y) of F passes
  // closer than tool_keepout_mm to the column.
  bool passes_column(double ax, double ay, double x_mm, double y_mm) const;
  // For an elevation move from the arm (joints known, tool up) whose straight
  // line passes the column and needs no configuration change: a point around
  // the column, reachable as the arm is, that a straight leg reaches; nullopt
  // otherwise.
  std::optional<std::pair<double, double>> column_waypoint(const ArmModel& arm, double x_mm,
                                                           double y_mm) const;

 private:
  std::optional<Goal> step(const Scene& scene);
  std::optional<Goal> start_over(const Scene& scene);
  std::optional<Goal> verify(const Scene& scene);
  std::optional<Goal> watch_turn(const Scene& scene);
  // While the tool waits lowered for the target: another sheep needing saving
  // that would leave the field before the arm, raised only after the rest of
  // this wait (wait_left_s), could reach it, but not if it went now.
  bool another_sheep_needs_the_arm(const Scene& scene, double wait_left_s) const;
  std::optional<Goal> send(const Scene& scene, Plane plane, double x_mm, double y_mm,
                           double theta_rad, int target, Phase next);
  std::optional<Goal> raise(const Scene& scene);
  // The next leg towards the park position (lower-right corner).
  std::optional<Goal> park(const Scene& scene);
  const Sheep* find_target(const Scene& scene) const;
  void set_phase(Phase phase);

  FieldRules rules_;
  ArmConfiguration arm_configuration_;
  Phase phase_ = Phase::kChoosing;
  PlannerStatus status_;

  struct Outstanding {
    Goal goal;
    double deadline_s = 0.0;
  };
  std::optional<Outstanding> outstanding_;
  // Result of the last goal, consumed by the next job: true = done.
  std::optional<bool> last_result_;
  int64_t next_goal_id_ = 1;
  int target_ = -1;
  Intercept intercept_;
  int corrections_ = 0;
  int raise_failures_ = 0;
  double turn_deadline_s_ = 0.0;
  bool target_saved_ = false;
  bool ignores_other_sheep_ = false;
  int consecutive_failures_ = 0;
  bool backoff_pending_ = false;
  double retry_after_s_ = -1e300;
  double body_over_tool_since_s_ = -1.0;    // -1: the target's body is not over the tool
  std::map<int, double> cooldown_until_s_;  // sheep id -> time it may be a candidate again
  // Sheep saved and not seen (visible) since: their velocity is the one from
  // before the touch, so they are no candidates until seen again.
  std::set<int> unseen_since_save_;
};

}  // namespace ephor::planner
