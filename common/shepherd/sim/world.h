#pragma once
// World: the simulated shepherding field (paper 003, section 1.1) - N Lego
// "sheep" driving in straight lines at constant speed, bumping into each other
// and into the PUMA's pedestal (Box2D rigid bodies), escaping over the field
// edge, and turned toward the field centre when the lowered manipulator
// touches them.
//
// Frames and units: field frame F of common/geometry/workcell.h, mm, s, rad
// (headings from +x towards +y). No wall clock inside: the caller advances
// time with step(dt), so benchmarks can run much faster than real time. The
// same config (seed included) and the same sequence of calls give the same
// world, bit for bit.
//
// Collisions: the wool makes them elastic (paper 003, section 4.1: bare Lego
// sheep clumped, woolled ones did not), so a sheep driving into another sheep
// or the pedestal bounces off - its heading is reflected about the contact
// normal. A sheep wedged for 2 s (under 30 % of its speed) turns away by a
// random 90-180 degrees.
//
// Threading: not thread-safe; one owner calls everything.

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "common/geometry/workcell.h"

class b2Body;

namespace ephor::sim {

struct WorldConfig {
  geometry::Workcell workcell;  // field size, planes, pedestal (F, mm)
  int sheep = 4;                // sheep on the field at the start and kept by re-entry
  uint64_t seed = 1;

  // Each sheep drives at speed_mm_s * (1 + speed_spread * U(-1, 1)), fixed per sheep.
  double speed_mm_s = 8.0;
  double speed_spread = 0.2;
  // Slow heading wander (the paper's Lego sheep did not drive quite straight):
  // the turn rate is an Ornstein-Uhlenbeck process with this standard deviation
  // (rad/s) and correlation time (s). 0 = perfectly straight.
  double wander_rad_s = 0.02;
  double wander_time_s = 5.0;

  // An escaped sheep re-enters from a random point of the field edge after this
  // delay (s), heading inward within +- entry_angle_rad of the inward normal.
  // Negative = escaped sheep never come back.
  double reentry_s = 5.0;
  double entry_angle_rad = 0.8;

  // The Lego sheep: 9 x 3.5 in body; the wool mark is a disc centred on the
  // body centre (so the mark centre is the sheep's position), on its back.
  double body_length_mm = 229.0;
  double body_width_mm = 89.0;
  double body_height_mm = 50.0;    // top of the body above the table (z in F)
  double mark_diameter_mm = 42.0;  // about 16 px in the 512 x 482 image
  double mark_height_mm = 52.0;    // z of the mark's top surface in F

  // The manipulator touches a sheep when its tip is at or below
  // object_plane_z + touch_height_mm and within touch_radius_mm of the body's
  // footprint.
  double touch_height_mm = 20.0;
  double touch_radius_mm = 15.0;
  // A touched sheep is turned the way the manipulator faces (the tool's
  // orientation theta, set_tool_tip): the paper's manipulator is "oriented to
  // catch" the sheep and redirects it toward the centre. false, or while the
  // orientation is unknown: straight at the field centre.
  bool touch_turns_along_tool = true;

  // Switches for measuring what each part of the world costs the system
  // (issue 13; the planners' kinematic stand-in has neither): sheep that pass
  // through each other, and a pedestal the sheep pass through.
  bool sheep_collisions = true;
  bool pedestal = true;

  // step(dt) subdivides into physics steps no longer than this (s).
  double max_substep_s = 0.005;
};

// Throws std::invalid_argument naming the first bad field.
void validate(const WorldConfig& config);

// One sheep as the world sees it (F, mm).
struct SheepState {
  int32_t id = 0;               // a re-entering or added sheep gets a new id
  Eigen::Vector2d centre_mm;    // body and mark centre in F (x, y)
  double body_angle_rad = 0.0;  // direction the sheep faces (and drives)
  Eigen::Vector2d velocity_mm_s;
  double drive_speed_mm_s = 0.0;  // the sheep's own constant speed
  bool on_field = true;
  // Direction of travel: the velocity's direction, or the body angle when nearly still.
  double heading_rad() const;
  double speed_mm_s() const { return velocity_mm_s.norm(); }
};

class World {
 public:
  explicit World(WorldConfig config);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  // Advances the world by dt_s (> 0, finite) seconds of simulated time.
  void step(double dt_s);

  // Where the manipulator's tip is now (F, mm), or nullopt when unknown, and
  // which way it faces (theta, rad about +z of F; nullopt: unknown). Held
  // until changed; sampled by every step.
  void set_tool_tip(const std::optional<Eigen::Vector3d>& tip_mm,
                    std::optional<double> theta_rad = std::nullopt);

  // Desired herd size (>= 0): missing sheep enter from the edge now, surplus
  // sheep (pending re-entries first, then the newest) are removed.
  void set_sheep_count(int count);
  // Restarts with a new seed (counters, time and ids from zero).
  void reset(uint64_t seed);

  // Places one sheep (for tests and scenarios); returns its id. Throws
  // std::invalid_argument when outside the field or not finite.
  int32_t add_sheep(double x_mm, double y_mm, double heading_rad, double speed_mm_s);

  std::vector<SheepState> sheep() const;
  int32_t escapes() const { return escapes_; }
  int32_t saves() const { return saves_; }
  double time_s() const { return time_s_; }
  const WorldConfig& config() const { return config_; }

  // Deepest overlap between any two bodies (or a body and the pedestal), mm;
  // 0 when nothing overlaps. For tests of the collision handling.
  double deepest_penetration_mm() const;

 private:
  struct Sheep;
  struct Physics;

  void build(uint64_t seed);
  void physics_step(double dt_s);
  void drive(Sheep& s, double dt_s);
  void set_heading(Sheep& s, double heading_rad);
  void bounce(b2Body* body, const Eigen::Vector2d& into_obstacle);
  void unblock(Sheep& s, double dt_s);
  void check_touches();
  void check_escapes();
  void process_reentries();
  bool spawn_at_edge();
  int32_t create_sheep(double x_mm, double y_mm, double heading_rad, double speed_mm_s);
  bool area_free(double x_mm, double y_mm, double heading_rad) const;
  double draw_speed();

  WorldConfig config_;
  std::unique_ptr<Physics> physics_;
  std::vector<std::unique_ptr<Sheep>> sheep_;
  std::vector<double> reentry_due_s_;  // sim times at which an escaped sheep comes back
  std::optional<Eigen::Vector3d> tool_tip_mm_;
  std::optional<double> tool_theta_rad_;
  int32_t next_id_ = 1;
  int32_t escapes_ = 0;
  int32_t saves_ = 0;
  double time_s_ = 0.0;
};

}  // namespace ephor::sim
