#include "common/catch/sim/board_world.h"

#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>

#include <box2d/box2d.h>

namespace ephor::catching {
namespace {

constexpr double kMmPerUnit = 10.0;  // see the header: Box2D's tolerances
constexpr int kVelocityIterations = 8;
constexpr int kPositionIterations = 3;
// Impacts slower than this along the normal do not bounce (mm/s): keeps a
// ball that rests against a rail or a peg from chattering.
constexpr double kRestitutionThresholdMmS = 10.0;

float to_units(double mm) { return static_cast<float>(mm / kMmPerUnit); }
double to_mm(float units) { return static_cast<double>(units) * kMmPerUnit; }

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("board world: " + what);
}

}  // namespace

struct BoardWorld::Physics {
  explicit Physics(const b2Vec2& gravity) : world(gravity) { world.SetAllowSleeping(false); }
  b2World world;
  b2Body* ball = nullptr;
  int64_t steps = 0;  // fixed steps since the release
  Eigen::Vector2d position_mm = Eigen::Vector2d::Zero();
  Eigen::Vector2d velocity_mm_s = Eigen::Vector2d::Zero();
};

BoardWorld::BoardWorld(const BoardSpec& board, double incline_rad, const std::vector<Peg>& pegs,
                       double peg_diameter_mm, BoardWorldConfig config)
    : board_(board),
      incline_rad_(incline_rad),
      pegs_(pegs),
      peg_radius_mm_(0.5 * peg_diameter_mm),
      config_(config) {
  require(std::isfinite(board.width_mm) && std::isfinite(board.height_mm) &&
              std::isfinite(board.ball_diameter_mm) && board.ball_diameter_mm > 0.0 &&
              board.width_mm > board.ball_diameter_mm && board.height_mm > board.ball_diameter_mm,
          "board must be larger than the ball, ball diameter > 0");
  require(std::isfinite(incline_rad) && incline_rad > 0.0 && incline_rad < 0.5 * std::numbers::pi,
          "incline must be in (0, 90) deg");
  require(std::isfinite(peg_diameter_mm) && peg_diameter_mm > 0.0, "peg diameter must be > 0");
  for (const Peg& p : pegs_)
    require(board_.on_board(p.x_mm, p.y_mm), "peg at (" + std::to_string(p.x_mm) + ", " +
                                                 std::to_string(p.y_mm) + ") mm is off the board");
  require(std::isfinite(config_.step_s) && config_.step_s > 0.0 && config_.step_s <= 0.01,
          "step_s must be in (0, 0.01]");
  require(std::isfinite(config_.restitution) && config_.restitution >= 0.0 &&
              config_.restitution <= 1.0,
          "restitution must be in [0, 1]");
  require(std::isfinite(config_.stall_limit_s) && config_.stall_limit_s > 0.0,
          "stall_limit_s must be > 0");
  slope_accel_mm_s2_ = 5.0 / 7.0 * kGravityMmS2 * std::sin(incline_rad_);
  // W's gravity in B (board_to_world: y_B = (-cos i, 0, -sin i), z_B = (-sin i, 0, cos i)).
  gravity_b_mm_s2_ = Eigen::Vector3d(0.0, kGravityMmS2 * std::sin(incline_rad_),
                                     -kGravityMmS2 * std::cos(incline_rad_));
}

BoardWorld::BoardWorld(const CatchScenario& s, BoardWorldConfig config)
    : BoardWorld(s.board, s.placement.incline_rad, s.pegs, s.peg_diameter_mm, config) {}

BoardWorld::~BoardWorld() = default;
BoardWorld::BoardWorld(BoardWorld&&) noexcept = default;
BoardWorld& BoardWorld::operator=(BoardWorld&&) noexcept = default;

std::unique_ptr<BoardWorld::Physics> BoardWorld::make_physics(const Release& r) const {
  auto p = std::make_unique<Physics>(b2Vec2(0.0f, to_units(slope_accel_mm_s2_)));
  b2BodyDef fixed_def;
  fixed_def.type = b2_staticBody;
  b2Body* fixed = p->world.CreateBody(&fixed_def);
  const float restitution = static_cast<float>(config_.restitution);
  const float threshold = to_units(kRestitutionThresholdMmS);

  // Rails: the side edges run a ball diameter past the bottom edge so that a
  // ball leaving the board near a side is still guided when it crosses.
  const float w = to_units(board_.width_mm);
  const float h_end = to_units(board_.height_mm + board_.ball_diameter_mm);
  const b2Vec2 rails[3][2] = {{b2Vec2(0.0f, 0.0f), b2Vec2(0.0f, h_end)},
                              {b2Vec2(w, 0.0f), b2Vec2(w, h_end)},
                              {b2Vec2(0.0f, 0.0f), b2Vec2(w, 0.0f)}};
  for (const auto& rail : rails) {
    b2EdgeShape edge;
    edge.SetTwoSided(rail[0], rail[1]);
    b2FixtureDef fd;
    fd.shape = &edge;
    fd.friction = 0.0f;
    fd.restitution = restitution;
    fd.restitutionThreshold = threshold;
    fixed->CreateFixture(&fd);
  }
  for (const Peg& peg : pegs_) {
    b2CircleShape circle;
    circle.m_p.Set(to_units(peg.x_mm), to_units(peg.y_mm));
    circle.m_radius = to_units(peg_radius_mm_);
    b2FixtureDef fd;
    fd.shape = &circle;
    fd.friction = 0.0f;
    fd.restitution = restitution;
    fd.restitutionThreshold = threshold;
    fixed->CreateFixture(&fd);
  }

  b2BodyDef ball_def;
  ball_def.type = b2_dynamicBody;
  ball_def.bullet = true;
  ball_def.fixedRotation = true;  // no friction: spin would never change
  ball_def.position.Set(to_units(r.x_mm), to_units(r.y_mm));
  ball_def.linearVelocity.Set(to_units(r.vx_mm_s), to_units(r.vy_mm_s));
  p->ball = p->world.CreateBody(&ball_def);
  b2CircleShape ball_shape;
  ball_shape.m_radius = to_units(board_.ball_radius_mm());
  b2FixtureDef fd;
  fd.shape = &ball_shape;
  fd.density = 1.0f;
  fd.friction = 0.0f;
  fd.restitution = restitution;
  fd.restitutionThreshold = threshold;
  p->ball->CreateFixture(&fd);

  p->position_mm = Eigen::Vector2d(to_mm(ball_def.position.x), to_mm(ball_def.position.y));
  p->velocity_mm_s =
      Eigen::Vector2d(to_mm(ball_def.linearVelocity.x), to_mm(ball_def.linearVelocity.y));
  return p;
}

void BoardWorld::fixed_step(Physics& p, const Release& r, std::optional<BoardExit>& exit) const {
  const Eigen::Vector2d p0 = p.position_mm, v0 = p.velocity_mm_s;
  p.world.Step(static_cast<float>(config_.step_s), kVelocityIterations, kPositionIterations);
  const b2Vec2 pos = p.ball->GetPosition();
  const b2Vec2 vel = p.ball->GetLinearVelocity();
  p.position_mm = Eigen::Vector2d(to_mm(pos.x), to_mm(pos.y));
  p.velocity_mm_s = Eigen::Vector2d(to_mm(vel.x), to_mm(vel.y));
  ++p.steps;
  const double h = board_.height_mm;
  if (p0.y() < h && p.position_mm.y() >= h) {
    const double f = (h - p0.y()) / (p.position_mm.y() - p0.y());
    BoardExit e;
    e.time_s = r.time_s + (static_cast<double>(p.steps - 1) + f) * config_.step_s;
    e.x_b_mm = p0.x() + f * (p.position_mm.x() - p0.x());
    e.velocity_b_mm_s = v0 + f * (p.velocity_mm_s - v0);
    exit = e;
  }
}

void BoardWorld::release(double x_mm, double y_mm, double vx_mm_s, double vy_mm_s) {
  const double r = board_.ball_radius_mm();
  require(std::isfinite(x_mm) && std::isfinite(y_mm) && x_mm >= r && x_mm <= board_.width_mm - r &&
              y_mm >= r && y_mm < board_.height_mm,
          "release point (" + std::to_string(x_mm) + ", " + std::to_string(y_mm) +
              ") mm must be in [r, width - r] x [r, height)");
  require(std::isfinite(vx_mm_s) && std::isfinite(vy_mm_s), "release velocity must be finite");
  for (const Peg& p : pegs_)
    require(std::hypot(p.x_mm - x_mm, p.y_mm - y_mm) >= r + peg_radius_mm_,
            "release point overlaps the peg at (" + std::to_string(p.x_mm) + ", " +
                std::to_string(p.y_mm) + ") mm");
  release_ = Release{time_s_, x_mm, y_mm, vx_mm_s, vy_mm_s};
  physics_ = make_physics(*release_);
  exit_.reset();
  stalled_ = false;
}

void BoardWorld::step(double dt_s) {
  require(std::isfinite(dt_s) && dt_s >= 0.0, "step dt must be >= 0");
  time_s_ += dt_s;
  if (!release_ || exit_ || stalled_) return;
  // Steps due by now, counted from the release so that rounding never drifts.
  const auto due =
      static_cast<int64_t>(std::floor((time_s_ - release_->time_s) / config_.step_s + 1e-9));
  const auto stall_steps = static_cast<int64_t>(std::ceil(config_.stall_limit_s / config_.step_s));
  while (physics_->steps < due && !exit_) {
    fixed_step(*physics_, *release_, exit_);
    if (!exit_ && physics_->steps >= stall_steps) {
      stalled_ = true;
      break;
    }
  }
}

BallState BoardWorld::state() const {
  BallState s;
  s.time_s = time_s_;
  if (!release_) return s;
  s.released = true;
  const double r = board_.ball_radius_mm();
  if (exit_) {
    const double tau = time_s_ - exit_->time_s;
    const Eigen::Vector3d p0(exit_->x_b_mm, board_.height_mm, r);
    const Eigen::Vector3d v0(exit_->velocity_b_mm_s.x(), exit_->velocity_b_mm_s.y(), 0.0);
    s.position_b_mm = p0 + v0 * tau + 0.5 * gravity_b_mm_s2_ * tau * tau;
    s.velocity_b_mm_s = v0 + gravity_b_mm_s2_ * tau;
    return s;
  }
  s.on_board = true;
  s.stalled = stalled_;
  const Physics& p = *physics_;
  if (stalled_) {
    s.position_b_mm = Eigen::Vector3d(p.position_mm.x(), p.position_mm.y(), r);
    return s;
  }
  const double ahead = time_s_ - (release_->time_s + static_cast<double>(p.steps) * config_.step_s);
  const Eigen::Vector2d pos = p.position_mm + p.velocity_mm_s * ahead;
  s.position_b_mm = Eigen::Vector3d(pos.x(), pos.y(), r);
  s.velocity_b_mm_s = Eigen::Vector3d(p.velocity_mm_s.x(), p.velocity_mm_s.y(), 0.0);
  return s;
}

SimulatedExit BoardWorld::predict_exit() const {
  SimulatedExit out;
  if (!release_) throw std::logic_error("board world: predict_exit() before any release");
  if (exit_ || stalled_) {
    out.exit = exit_;
    out.stalled = stalled_;
    return out;
  }
  auto copy = make_physics(*release_);
  const auto stall_steps = static_cast<int64_t>(std::ceil(config_.stall_limit_s / config_.step_s));
  while (!out.exit && copy->steps < stall_steps) fixed_step(*copy, *release_, out.exit);
  out.stalled = !out.exit;
  return out;
}

}  // namespace ephor::catching
