#pragma once
// KinematicField: a tiny kinematic stand-in for ephor-sim + ephor-arm, for
// closed-loop tests and benchmarks of the planners without LCM, vision or
// Box2D. Sheep are points with a 229 x 89 mm body moving in straight lines
// at constant speed; the arm tool is a point moving in a straight line at
// its speed cap in 3-D between the elevation plane (z = 200 mm) and the
// object plane (z = 30 mm); a lowered tool inside a sheep's body turns that
// sheep toward the field centre. A sheep whose centre leaves the field is an
// escape and re-enters from a random edge point after a delay. By default no
// collisions and no pedestal (KinematicFieldConfig::pedestal and
// sheep_collisions add ephor-sim's bounces). Deterministic for a seed. All in
// F: mm, mm/s, s.
//
// The arm can instead be a real one (KinematicFieldConfig::arm_motion, e.g.
// PumaArmMotion: the PUMA 560 with ephor-arm's motion planner), so that a
// planner meets configuration changes and detours around the column here
// as it does on the full system.

#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <utility>
#include <vector>

#include "procs/shepherd/planner/herd_types.h"

namespace ephor::planner {

// How the stand-in's tool gets to a goal, when not as a point at its speed cap.
class ArmMotion {
 public:
  virtual ~ArmMotion() = default;
  // Starts a motion of the tool tip, pointing down with orientation theta
  // (rad), to (x, y, z) of F (mm) from where it is now. False when the arm
  // refuses the goal (it then stays where it is).
  virtual bool start(double x_mm, double y_mm, double z_mm, double theta_rad) = 0;
  // Advances the motion by dt_s; true once it has ended.
  virtual bool step(double dt_s) = 0;
  // Tool tip in F, mm.
  virtual std::array<double, 3> tool_mm() const = 0;
  // The arm's joints, rad (what ARM_STATE tells the planner).
  virtual JointAngles joints() const = 0;
};

struct KinematicFieldConfig {
  geometry::Workcell workcell;
  int sheep = 4;
  uint32_t seed = 7;
  double sheep_speed_mm_s = 8.0;
  double sheep_speed_jitter = 0.2;  // each sheep's speed is uniform in speed * (1 +- jitter)
  double sheep_half_length_mm = 114.5;
  double sheep_half_width_mm = 44.5;
  double tool_radius_mm = 15.0;  // as ephor-sim's touch_radius_mm
  double arm_speed_mm_s = 300.0;
  double goal_latency_s = 0.05;  // before the arm starts a goal (comm)
  double respawn_s = 5.0;
  double entry_angle_rad = 0.8;    // re-entry heading within this of the inward normal
  double start_margin_mm = 134.5;  // initial sheep this far inside the edges (ephor-sim's rule)
  // Imperfect sensing (0 = off): a turn shows in the reported velocity only
  // after velocity_lag_s (the world model's filter), and a sheep within
  // hide_radius_mm of the lowered tool is reported obscured with the
  // velocity it had before (the arm hides its mark from the camera).
  double velocity_lag_s = 0.0;
  double hide_radius_mm = 0.0;
  // ephor-sim's bounces (common/shepherd/sim/world.h), off by default so that
  // the stand-in stays the kinematic model its published figures are of: a
  // sheep driving into the pedestal (workcell.pedestal_radius_mm at the base)
  // or into another sheep has its heading reflected about the contact normal.
  // Contact is judged along the line between the centres, each body reaching
  // its rectangle's extent along that line: exact head-on and side-on, a
  // little early at a corner. A bounce is seen late like a touch (velocity_lag_s).
  bool pedestal = false;
  bool sheep_collisions = false;
  // A touched sheep is turned the way the lowered tool faces (its goal's
  // theta), as ephor-sim turns it (common/shepherd/sim/world.h
  // touch_turns_along_tool): the paper's manipulator is "oriented to catch"
  // the sheep and redirects it. false: straight at the field centre whatever
  // the tool's orientation (the stand-in before 2026-11-28).
  bool touch_turns_along_tool = true;
  double start_x_mm = 1219.0 - 60.0;  // the arm starts parked
  double start_y_mm = 60.0;
  // A real arm instead of the point (it starts where it is, not at
  // start_x/y); shared so that a config stays copyable.
  std::shared_ptr<ArmMotion> arm_motion;
};

class KinematicField {
 public:
  explicit KinematicField(const KinematicFieldConfig& config);
  // Starts with exactly these sheep (ids, positions and velocities kept)
  // instead of config.sheep random ones.
  KinematicField(const KinematicFieldConfig& config, const std::vector<Sheep>& initial);

  // Advances the world by dt_s.
  void step(double dt_s);
  // Sends a goal (replacing one still running, like a real arm would only
  // after the planner was told; the planners never do that).
  void send(const Goal& goal);
  // Goals finished since the last call: (goal_id, succeeded).
  std::vector<std::pair<int64_t, bool>> take_done();

  // What the planner sees: true sheep state (perfect tracking) and the arm.
  Scene scene(const ArmModel& arm_params) const;

  double now_s() const { return now_s_; }
  int escapes() const { return escapes_; }
  int touches() const { return touches_; }
  int sheep_on_field() const;

 private:
  struct SimSheep {
    int id;
    double x, y, heading, speed;
    bool on_field = true;
    double respawn_at_s = 0.0;
    bool touched_now = false;  // inside the lowered tool this step (one turn per touch)
    double old_heading = 0.0;  // before the last turn
    double turned_at_s = -1e9;
    double hidden_since_s = -1.0;  // -1: visible
  };
  void spawn_inside(SimSheep& s);
  void spawn_at_edge(SimSheep& s);
  void step_arm_motion(double dt_s);
  // The pedestal's and other sheep's bounces after a step (config_.pedestal,
  // config_.sheep_collisions).
  void bounce();
  // How far the body reaches from its centre along the unit vector (nx, ny), mm.
  double extent(const SimSheep& s, double nx, double ny) const;
  // Reflects the heading about the unit normal (nx, ny) pointing into the
  // obstacle, if the sheep drives into it.
  void reflect(SimSheep& s, double nx, double ny);

  KinematicFieldConfig config_;
  std::mt19937 rng_;
  std::vector<SimSheep> sheep_;
  int next_id_ = 1;
  double now_s_ = 0.0;
  double tool_x_, tool_y_, tool_z_;
  // The tool's orientation about +z of F, rad: the newest goal's theta once
  // the arm has started it (set before it arrives: the wrist turns on the way).
  double tool_theta_ = 0.0;
  std::optional<Goal> goal_;
  double goal_start_s_ = 0.0;
  bool goal_started_ = false;  // handed to config_.arm_motion
  std::vector<std::pair<int64_t, bool>> done_;
  int escapes_ = 0;
  int touches_ = 0;
};

}  // namespace ephor::planner
