#pragma once
// BoardWorld: the ball rolling down the inclined, pegged board (paper 000,
// section 2), simulated with Box2D in the board plane.
//
// Model:
// - The ball is a solid sphere rolling without slipping on the face, so its
//   centre accelerates down the slope at a = 5/7 g sin(incline) (the 2/5 m r^2
//   moment of inertia takes 2/7 of the drive), g = 9810 mm/s^2. Box2D sees a
//   frictionless disc of the ball's radius under gravity a along +y of B.
// - Pegs are static circles; the side edges x = 0 and x = width and the top
//   edge y = 0 are rails (static edges) that keep the ball on the board.
//   Impacts have restitution 0.5 at any speed and no friction impulse (the
//   ball rolls; its spin is not modelled).
// - The ball leaves the board when its centre crosses the bottom edge
//   y = height (it tips over the edge there); that crossing, linearly
//   interpolated between steps, is the exit event. From then on the ball
//   flies ballistically under full g in W (state() keeps reporting it, in B).
// - A ball that has not left the board stall_limit_s after its release
//   (wedged or balanced) is stalled; the world stops moving it.
//
// Units: the API is in mm and s, in the board frame B of
// common/catch/board_model.h. Box2D's length unit is 10 mm inside: its
// fixed tolerances (linear slop 0.005 units, edge skin 0.01 units) are tuned
// for bodies of 0.1 to 10 units, and would be 5 mm and 10 mm at one unit per
// metre - a quarter of the ball's radius. At 10 mm per unit they are 0.05 mm
// and 0.1 mm.
//
// Time: step(dt) advances the world's clock by dt; Box2D runs fixed steps of
// config.step_s counted from the release, and state() extrapolates the last
// fixed step to the clock (a fraction of one step). Deterministic: the same
// release and the same total time give the same trajectory whatever the
// sequence of step() calls.
//
// Threading: not thread-safe; one owner steps and reads it.

#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "common/catch/board_model.h"
#include "common/catch/sim/catch_scenario.h"

namespace ephor::catching {

struct BoardWorldConfig {
  double step_s = 0.001;        // Box2D's fixed step, s (0, 0.01]
  double restitution = 0.5;     // on pegs and rails
  double stall_limit_s = 10.0;  // a ball not out after this long is stalled
};

struct BallState {
  bool released = false;
  bool on_board = false;  // released and not yet over the bottom edge
  bool stalled = false;
  double time_s = 0.0;  // the world's clock
  // Ball centre in B, mm: z = ball radius on the board, then the flight.
  Eigen::Vector3d position_b_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_b_mm_s = Eigen::Vector3d::Zero();
};

// The ball's centre crossing the bottom edge y = height (B).
struct BoardExit {
  double time_s = 0.0;  // world clock
  double x_b_mm = 0.0;
  Eigen::Vector2d velocity_b_mm_s = Eigen::Vector2d::Zero();  // (vx, vy), vy > 0
};

// What predict_exit() foresees: the exit, or that the ball stalls.
struct SimulatedExit {
  std::optional<BoardExit> exit;
  bool stalled = false;  // exit is empty: the ball never leaves within the limit
};

class BoardWorld {
 public:
  // Throws std::invalid_argument for a bad board, incline (0, 90) deg, peg or
  // config.
  BoardWorld(const BoardSpec& board, double incline_rad, const std::vector<Peg>& pegs,
             double peg_diameter_mm, BoardWorldConfig config = {});
  explicit BoardWorld(const CatchScenario& scenario, BoardWorldConfig config = {});
  ~BoardWorld();
  BoardWorld(BoardWorld&&) noexcept;
  BoardWorld& operator=(BoardWorld&&) noexcept;

  // Puts the ball on the board at (x, y) of B with velocity (vx, vy) mm/s at
  // the current clock, replacing any ball. Throws std::invalid_argument when
  // the centre is off the board (x in [r, width - r], y in [r, height)) or
  // inside a peg.
  void release(double x_mm, double y_mm, double vx_mm_s, double vy_mm_s);
  void release(const BallRelease& r) { release(r.x_mm, r.y_mm, r.vx_mm_s, r.vy_mm_s); }

  // Advances the clock by dt_s >= 0.
  void step(double dt_s);

  double time_s() const { return time_s_; }
  BallState state() const;
  // The exit, once the ball has left the board.
  const std::optional<BoardExit>& exit() const { return exit_; }
  bool stalled() const { return stalled_; }

  // Runs a copy of the world - rebuilt and replayed from the release, so
  // bit-identical to what this world will do - to the exit or the stall
  // limit, leaving this world untouched. Costs ~0.8 us per fixed step: about
  // 1.4 ms for a whole descent.
  SimulatedExit predict_exit() const;

  // The ball's acceleration down the slope, 5/7 g sin(incline), mm/s^2.
  double slope_acceleration_mm_s2() const { return slope_accel_mm_s2_; }
  const BoardSpec& board() const { return board_; }
  const BoardWorldConfig& config() const { return config_; }

 private:
  struct Physics;
  struct Release {
    double time_s, x_mm, y_mm, vx_mm_s, vy_mm_s;
  };
  std::unique_ptr<Physics> make_physics(const Release& r) const;
  // One fixed step of `p`; sets `exit` when the ball crosses the bottom edge.
  void fixed_step(Physics& p, const Release& r, std::optional<BoardExit>& exit) const;

  BoardSpec board_;
  double incline_rad_ = 0.0;
  std::vector<Peg> pegs_;
  double peg_radius_mm_ = 6.0;
  BoardWorldConfig config_;
  double slope_accel_mm_s2_ = 0.0;
  Eigen::Vector3d gravity_b_mm_s2_ = Eigen::Vector3d::Zero();  // full g, for the flight

  double time_s_ = 0.0;
  std::optional<Release> release_;
  std::unique_ptr<Physics> physics_;
  std::optional<BoardExit> exit_;
  bool stalled_ = false;
};

}  // namespace ephor::catching
