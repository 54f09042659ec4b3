#include "common/shepherd/sim/world.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

#include <box2d/box2d.h>

namespace ephor::sim {
namespace {

// Box2D is tuned for objects of 0.1 to 10 units; a unit of 100 mm puts a
// sheep at 2.3 x 0.9 units and Box2D's linear slop at 0.5 mm.
constexpr double kMmPerUnit = 100.0;
constexpr int kVelocityIterations = 8;
constexpr int kPositionIterations = 3;

// The sheep's drive: wheels that grip sideways and a motor that holds the
// sheep's own speed. Finite forces so that colliding sheep push, turn and slip
// past each other instead of stopping dead (mm/s^2, rad/s^2).
constexpr double kDriveAccelMmS2 = 300.0;
constexpr double kLateralGripMmS2 = 500.0;
constexpr double kTurnAccelRadS2 = 2.0;

// The wool makes collisions elastic (paper 003, section 4.1: bare Lego sheep
// clumped, woolled ones did not): a sheep driving into another body bounces
// off it - its heading is reflected about the contact normal - when its
// heading points into the obstacle by more than this (cosine).
constexpr double kBounceMinApproach = 0.05;
// A sheep that still makes less than this fraction of its speed for
// kBlockedS (wedged between others) turns away by a random 90-180 degrees.
constexpr double kBlockedSpeedFraction = 0.3;
constexpr double kBlockedS = 2.0;

// Keep new sheep this far from the corners when they enter (mm), so one does
// not enter through one edge and leave through the next.
constexpr double kEntryCornerMarginMm = 120.0;

float to_units(double mm) { return static_cast<float>(mm / kMmPerUnit); }
double to_mm(float units) { return static_cast<double>(units) * kMmPerUnit; }

double wrap_angle(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("sim world config: " + what);
}

}  // namespace

void validate(const WorldConfig& c) {
  const auto& w = c.workcell;
  require(std::isfinite(w.field_length_mm) && w.field_length_mm > 0.0,
          "field_length_mm must be > 0");
  require(std::isfinite(w.field_width_mm) && w.field_width_mm > 0.0, "field_width_mm must be > 0");
  require(c.sheep >= 0 && c.sheep <= 64,
          "sheep must be in [0, 64], got " + std::to_string(c.sheep));
  require(std::isfinite(c.speed_mm_s) && c.speed_mm_s >= 0.0 && c.speed_mm_s <= 1000.0,
          "speed_mm_s must be in [0, 1000]");
  require(std::isfinite(c.speed_spread) && c.speed_spread >= 0.0 && c.speed_spread < 1.0,
          "speed_spread must be in [0, 1)");
  require(std::isfinite(c.wander_rad_s) && c.wander_rad_s >= 0.0, "wander_rad_s must be >= 0");
  require(std::isfinite(c.wander_time_s) && c.wander_time_s > 0.0, "wander_time_s must be > 0");
  require(std::isfinite(c.reentry_s), "reentry_s must be finite (negative = never)");
  require(std::isfinite(c.entry_angle_rad) && c.entry_angle_rad >= 0.0 &&
              c.entry_angle_rad < std::numbers::pi / 2.0,
          "entry_angle_rad must be in [0, pi/2)");
  require(c.body_length_mm > 0.0 && c.body_width_mm > 0.0 && c.body_width_mm <= c.body_length_mm,
          "body must have 0 < width <= length");
  require(c.body_length_mm < 0.5 * std::min(w.field_length_mm, w.field_width_mm),
          "body_length_mm must be under half the field's smaller side");
  require(c.mark_diameter_mm > 0.0 && c.mark_diameter_mm <= c.body_width_mm,
          "mark_diameter_mm must be in (0, body_width_mm]");
  require(c.body_height_mm >= 0.0 && c.mark_height_mm >= c.body_height_mm,
          "need 0 <= body_height_mm <= mark_height_mm");
  require(c.touch_height_mm >= 0.0 && c.touch_radius_mm >= 0.0,
          "touch_height_mm and touch_radius_mm must be >= 0");
  require(std::isfinite(c.max_substep_s) && c.max_substep_s > 0.0 && c.max_substep_s <= 0.05,
          "max_substep_s must be in (0, 0.05]");
}

double SheepState::heading_rad() const {
  if (velocity_mm_s.norm() > 1.0) return std::atan2(velocity_mm_s.y(), velocity_mm_s.x());
  return body_angle_rad;
}

struct World::Sheep {
  int32_t id = 0;
  b2Body* body = nullptr;
  double drive_speed_mm_s = 0.0;
  double turn_rate_rad_s = 0.0;  // the wander process
  double blocked_s = 0.0;        // how long it has been held up
  bool touched = false;          // the manipulator is touching it now
};

namespace {

// Contacts that began during a Box2D step; bodies may not be changed inside
// the step, so the bounces are applied after it.
struct ContactStart {
  b2Body* a;
  b2Body* b;
  Eigen::Vector2d normal;  // from a to b
};

class ContactRecorder : public b2ContactListener {
 public:
  void BeginContact(b2Contact* contact) override {
    if (contact->GetFixtureA()->IsSensor() || contact->GetFixtureB()->IsSensor()) return;
    b2WorldManifold wm;
    contact->GetWorldManifold(&wm);
    starts.push_back(
        {contact->GetFixtureA()->GetBody(), contact->GetFixtureB()->GetBody(),
         Eigen::Vector2d(static_cast<double>(wm.normal.x), static_cast<double>(wm.normal.y))});
  }
  std::vector<ContactStart> starts;
};

}  // namespace

struct World::Physics {
  explicit Physics(uint64_t seed) : world(b2Vec2(0.0f, 0.0f)), rng(seed) {
    world.SetAllowSleeping(false);
    world.SetContactListener(&contacts);
  }
  ContactRecorder contacts;  // outlives `world`, which points to it
  b2World world;
  b2Body* pedestal = nullptr;
  std::mt19937_64 rng;
};

World::World(WorldConfig config) : config_(std::move(config)) {
  validate(config_);
  build(config_.seed);
}

World::~World() = default;

void World::build(uint64_t seed) {
  sheep_.clear();
  physics_ = std::make_unique<Physics>(seed);
  reentry_due_s_.clear();
  next_id_ = 1;
  escapes_ = 0;
  saves_ = 0;
  time_s_ = 0.0;

  const auto& w = config_.workcell;
  b2BodyDef pedestal_def;
  pedestal_def.type = b2_staticBody;
  pedestal_def.position.Set(to_units(w.base_x_mm), to_units(w.base_y_mm));
  physics_->pedestal = physics_->world.CreateBody(&pedestal_def);
  b2CircleShape column;
  column.m_radius = to_units(w.pedestal_radius_mm);
  b2FixtureDef column_fixture;
  column_fixture.shape = &column;
  column_fixture.isSensor = !config_.pedestal;  // a sensor is there but stops nothing
  physics_->pedestal->CreateFixture(&column_fixture);

  // Initial herd: uniformly placed away from the edges, the pedestal and each
  // other, facing random directions.
  const double margin = 0.5 * config_.body_length_mm + 20.0;
  std::uniform_real_distribution<double> ux(margin, w.field_length_mm - margin);
  std::uniform_real_distribution<double> uy(margin, w.field_width_mm - margin);
  std::uniform_real_distribution<double> ua(-std::numbers::pi, std::numbers::pi);
  for (int i = 0; i < config_.sheep; ++i) {
    bool placed = false;
    for (int attempt = 0; attempt < 2000 && !placed; ++attempt) {
      const double x = ux(physics_->rng);
      const double y = uy(physics_->rng);
      const double a = ua(physics_->rng);
      if (!area_free(x, y, a)) continue;
      create_sheep(x, y, a, draw_speed());
      placed = true;
    }
    if (!placed)
      throw std::invalid_argument("sim world config: cannot place " +
                                  std::to_string(config_.sheep) +
                                  " sheep apart from each other on the field");
  }
}

double World::draw_speed() {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return config_.speed_mm_s * (1.0 + config_.speed_spread * u(physics_->rng));
}

bool World::area_free(double x_mm, double y_mm, double /*heading_rad*/) const {
  // Conservative: any orientation of two bodies whose centres are a body
  // length apart cannot overlap.
  const auto& w = config_.workcell;
  const double clear = config_.body_length_mm + 10.0;
  if (std::hypot(x_mm - w.base_x_mm, y_mm - w.base_y_mm) <
      w.pedestal_radius_mm + 0.5 * config_.body_length_mm + 10.0)
    return false;
  for (const auto& s : sheep_) {
    const b2Vec2 p = s->body->GetPosition();
    if (std::hypot(x_mm - to_mm(p.x), y_mm - to_mm(p.y)) < clear) return false;
  }
  return true;
}

int32_t World::create_sheep(double x_mm, double y_mm, double heading_rad, double speed_mm_s) {
  b2BodyDef def;
  def.type = b2_dynamicBody;
  def.position.Set(to_units(x_mm), to_units(y_mm));
  def.angle = static_cast<float>(heading_rad);
  def.linearVelocity.Set(to_units(speed_mm_s * std::cos(heading_rad)),
                         to_units(speed_mm_s * std::sin(heading_rad)));
  b2Body* body = physics_->world.CreateBody(&def);
  b2PolygonShape box;
  box.SetAsBox(to_units(0.5 * config_.body_length_mm), to_units(0.5 * config_.body_width_mm));
  b2FixtureDef fixture;
  fixture.shape = &box;
  fixture.density = 1.0f;
  fixture.friction = 0.3f;     // Lego against Lego
  fixture.restitution = 0.1f;  // the "wool" makes collisions soft
  // Fixtures of one negative group never collide with each other (Box2D's
  // filtering), but still with the pedestal.
  if (!config_.sheep_collisions) fixture.filter.groupIndex = -1;
  body->CreateFixture(&fixture);

  auto s = std::make_unique<Sheep>();
  s->id = next_id_++;
  s->body = body;
  body->GetUserData().pointer = reinterpret_cast<uintptr_t>(s.get());
  s->drive_speed_mm_s = speed_mm_s;
  sheep_.push_back(std::move(s));
  return sheep_.back()->id;
}

int32_t World::add_sheep(double x_mm, double y_mm, double heading_rad, double speed_mm_s) {
  if (!std::isfinite(x_mm) || !std::isfinite(y_mm) || !std::isfinite(heading_rad) ||
      !std::isfinite(speed_mm_s) || speed_mm_s < 0.0)
    throw std::invalid_argument(
        "add_sheep: position, heading and speed must be finite, speed >= 0");
  if (!config_.workcell.inside_field(x_mm, y_mm))
    throw std::invalid_argument("add_sheep: (" + std::to_string(x_mm) + ", " +
                                std::to_string(y_mm) + ") mm is outside the field");
  return create_sheep(x_mm, y_mm, heading_rad, speed_mm_s);
}

void World::set_tool_tip(const std::optional<Eigen::Vector3d>& tip_mm,
                         std::optional<double> theta_rad) {
  tool_theta_rad_ = theta_rad && std::isfinite(*theta_rad) ? theta_rad : std::nullopt;
  if (tip_mm && !tip_mm->allFinite()) {
    tool_tip_mm_.reset();
    return;
  }
  tool_tip_mm_ = tip_mm;
}

void World::set_sheep_count(int count) {
  if (count < 0) throw std::invalid_argument("set_sheep_count: count must be >= 0");
  int total = static_cast<int>(sheep_.size() + reentry_due_s_.size());
  while (total > count && !reentry_due_s_.empty()) {
    reentry_due_s_.pop_back();
    --total;
  }
  while (total > count && !sheep_.empty()) {
    physics_->world.DestroyBody(sheep_.back()->body);
    sheep_.pop_back();
    --total;
  }
  // Missing sheep walk in from the edge at once (through the re-entry queue,
  // which retries while the edge is crowded).
  for (; total < count; ++total) reentry_due_s_.push_back(time_s_);
}

void World::reset(uint64_t seed) {
  config_.seed = seed;
  build(seed);
}

void World::step(double dt_s) {
  if (!std::isfinite(dt_s) || dt_s <= 0.0)
    throw std::invalid_argument("World::step: dt must be finite and > 0, got " +
                                std::to_string(dt_s));
  const int n = static_cast<int>(std::ceil(dt_s / config_.max_substep_s - 1e-9));
  const double h = dt_s / n;
  for (int i = 0; i < n; ++i) {
    physics_step(h);
    time_s_ += h;
    check_touches();
    check_escapes();
    process_reentries();
  }
}

void World::physics_step(double dt_s) {
  for (auto& s : sheep_) drive(*s, dt_s);
  physics_->contacts.starts.clear();
  physics_->world.Step(static_cast<float>(dt_s), kVelocityIterations, kPositionIterations);
  for (const auto& c : physics_->contacts.starts) {
    bounce(c.a, c.normal);
    bounce(c.b, -c.normal);
  }
  for (auto& s : sheep_) unblock(*s, dt_s);
}

void World::set_heading(Sheep& s, double heading_rad) {
  s.body->SetTransform(s.body->GetPosition(), static_cast<float>(heading_rad));
  s.body->SetLinearVelocity(b2Vec2(to_units(s.drive_speed_mm_s * std::cos(heading_rad)),
                                   to_units(s.drive_speed_mm_s * std::sin(heading_rad))));
  s.body->SetAngularVelocity(0.0f);
}

void World::bounce(b2Body* body, const Eigen::Vector2d& into_obstacle) {
  auto* s = reinterpret_cast<Sheep*>(body->GetUserData().pointer);
  if (s == nullptr) return;  // the pedestal
  const double a = static_cast<double>(body->GetAngle());
  const Eigen::Vector2d fwd(std::cos(a), std::sin(a));
  const double approach = fwd.dot(into_obstacle);
  if (approach <= kBounceMinApproach) return;  // moving away from it, or grazing
  const Eigen::Vector2d out = fwd - 2.0 * approach * into_obstacle;
  set_heading(*s, std::atan2(out.y(), out.x()));
}

void World::unblock(Sheep& s, double dt_s) {
  const double a = static_cast<double>(s.body->GetAngle());
  const b2Vec2 v = s.body->GetLinearVelocity();
  const double forward = to_mm(v.x) * std::cos(a) + to_mm(v.y) * std::sin(a);
  if (forward >= kBlockedSpeedFraction * s.drive_speed_mm_s) {
    s.blocked_s = 0.0;
    return;
  }
  s.blocked_s += dt_s;
  if (s.blocked_s < kBlockedS) return;
  std::uniform_real_distribution<double> turn(0.5 * std::numbers::pi, std::numbers::pi);
  std::bernoulli_distribution left(0.5);
  const double t = turn(physics_->rng);
  set_heading(s, wrap_angle(a + (left(physics_->rng) ? t : -t)));
  s.blocked_s = 0.0;
}

void World::drive(Sheep& s, double dt_s) {
  // Wander: Ornstein-Uhlenbeck turn rate, exact discretisation.
  if (config_.wander_rad_s > 0.0) {
    std::normal_distribution<double> n01(0.0, 1.0);
    const double decay = std::exp(-dt_s / config_.wander_time_s);
    s.turn_rate_rad_s = decay * s.turn_rate_rad_s +
                        config_.wander_rad_s * std::sqrt(1.0 - decay * decay) * n01(physics_->rng);
  }
  b2Body* b = s.body;
  const double m = static_cast<double>(b->GetMass());
  const double inertia = static_cast<double>(b->GetInertia());
  const double a = static_cast<double>(b->GetAngle());
  const Eigen::Vector2d fwd(std::cos(a), std::sin(a));
  const Eigen::Vector2d side(-fwd.y(), fwd.x());
  const b2Vec2 vb = b->GetLinearVelocity();
  const Eigen::Vector2d v(to_mm(vb.x), to_mm(vb.y));  // mm/s

  const double dv_fwd =
      std::clamp(s.drive_speed_mm_s - v.dot(fwd), -kDriveAccelMmS2 * dt_s, kDriveAccelMmS2 * dt_s);
  const double dv_side =
      std::clamp(-v.dot(side), -kLateralGripMmS2 * dt_s, kLateralGripMmS2 * dt_s);
  const Eigen::Vector2d impulse = m * (dv_fwd * fwd + dv_side * side) / kMmPerUnit;
  b->ApplyLinearImpulseToCenter(
      b2Vec2(static_cast<float>(impulse.x()), static_cast<float>(impulse.y())), true);
  const double dw = std::clamp(s.turn_rate_rad_s - static_cast<double>(b->GetAngularVelocity()),
                               -kTurnAccelRadS2 * dt_s, kTurnAccelRadS2 * dt_s);
  b->ApplyAngularImpulse(static_cast<float>(inertia * dw), true);
}

void World::check_touches() {
  const auto& w = config_.workcell;
  const bool lowered =
      tool_tip_mm_ && tool_tip_mm_->z() <= w.object_plane_z_mm + config_.touch_height_mm;
  const double hx = 0.5 * config_.body_length_mm + config_.touch_radius_mm;
  const double hy = 0.5 * config_.body_width_mm + config_.touch_radius_mm;
  for (auto& s : sheep_) {
    bool touching = false;
    if (lowered) {
      const b2Vec2 p = s->body->GetPosition();
      const double a = static_cast<double>(s->body->GetAngle());
      const Eigen::Vector2d d(tool_tip_mm_->x() - to_mm(p.x), tool_tip_mm_->y() - to_mm(p.y));
      const double along = d.x() * std::cos(a) + d.y() * std::sin(a);
      const double across = -d.x() * std::sin(a) + d.y() * std::cos(a);
      touching = std::abs(along) <= hx && std::abs(across) <= hy;
    }
    if (touching) {
      // Turned the way the tool faces (or toward the centre); it keeps being
      // turned while touched, but a touch counts as one save.
      if (!s->touched) ++saves_;
      const b2Vec2 p = s->body->GetPosition();
      const double heading =
          config_.touch_turns_along_tool && tool_theta_rad_
              ? *tool_theta_rad_
              : std::atan2(w.centre_y_mm() - to_mm(p.y), w.centre_x_mm() - to_mm(p.x));
      s->body->SetTransform(p, static_cast<float>(heading));
      s->body->SetLinearVelocity(b2Vec2(to_units(s->drive_speed_mm_s * std::cos(heading)),
                                        to_units(s->drive_speed_mm_s * std::sin(heading))));
      s->body->SetAngularVelocity(0.0f);
      s->turn_rate_rad_s = 0.0;
    }
    s->touched = touching;
  }
}

void World::check_escapes() {
  for (size_t i = 0; i < sheep_.size();) {
    const b2Vec2 p = sheep_[i]->body->GetPosition();
    if (config_.workcell.inside_field(to_mm(p.x), to_mm(p.y))) {
      ++i;
      continue;
    }
    physics_->world.DestroyBody(sheep_[i]->body);
    sheep_.erase(sheep_.begin() + static_cast<std::ptrdiff_t>(i));
    ++escapes_;
    if (config_.reentry_s >= 0.0) reentry_due_s_.push_back(time_s_ + config_.reentry_s);
  }
}

void World::process_reentries() {
  for (size_t i = 0; i < reentry_due_s_.size();) {
    // A crowded edge postpones the entry to a later step.
    if (reentry_due_s_[i] <= time_s_ && spawn_at_edge()) {
      reentry_due_s_.erase(reentry_due_s_.begin() + static_cast<std::ptrdiff_t>(i));
    } else {
      ++i;
    }
  }
}

bool World::spawn_at_edge() {
  const double len = config_.workcell.field_length_mm;
  const double wid = config_.workcell.field_width_mm;
  const double m = kEntryCornerMarginMm;
  // Arc length along the perimeter, corners excluded.
  const double bottom = len - 2.0 * m, side = wid - 2.0 * m;
  std::uniform_real_distribution<double> us(0.0, 2.0 * (bottom + side));
  std::uniform_real_distribution<double> ua(-config_.entry_angle_rad, config_.entry_angle_rad);
  constexpr double kInsideMm = 1.0;  // the centre starts just inside the edge
  for (int attempt = 0; attempt < 20; ++attempt) {
    double s = us(physics_->rng);
    double x, y, normal;
    if (s < bottom) {
      x = m + s, y = kInsideMm, normal = std::numbers::pi / 2.0;
    } else if ((s -= bottom) < side) {
      x = len - kInsideMm, y = m + s, normal = std::numbers::pi;
    } else if ((s -= side) < bottom) {
      x = len - m - s, y = wid - kInsideMm, normal = -std::numbers::pi / 2.0;
    } else {
      s -= bottom;
      x = kInsideMm, y = wid - m - s, normal = 0.0;
    }
    const double heading = wrap_angle(normal + ua(physics_->rng));
    if (!area_free(x, y, heading)) continue;
    create_sheep(x, y, heading, draw_speed());
    return true;
  }
  return false;
}

std::vector<SheepState> World::sheep() const {
  std::vector<SheepState> out;
  out.reserve(sheep_.size());
  for (const auto& s : sheep_) {
    const b2Vec2 p = s->body->GetPosition();
    const b2Vec2 v = s->body->GetLinearVelocity();
    SheepState st;
    st.id = s->id;
    st.centre_mm = {to_mm(p.x), to_mm(p.y)};
    st.body_angle_rad = wrap_angle(static_cast<double>(s->body->GetAngle()));
    st.velocity_mm_s = {to_mm(v.x), to_mm(v.y)};
    st.drive_speed_mm_s = s->drive_speed_mm_s;
    st.on_field = config_.workcell.inside_field(st.centre_mm.x(), st.centre_mm.y());
    out.push_back(st);
  }
  return out;
}

double World::deepest_penetration_mm() const {
  // Recomputed from the bodies' present transforms (the contact list's
  // manifolds are a step old, and stale after a bounce turns a sheep).
  double deepest = 0.0;
  const auto measure = [&](const b2Manifold& m, const b2Transform& xa, float ra,
                           const b2Transform& xb, float rb) {
    b2WorldManifold wm;
    wm.Initialize(&m, xa, ra, xb, rb);
    for (int i = 0; i < m.pointCount; ++i) deepest = std::max(deepest, -to_mm(wm.separations[i]));
  };
  const auto* column =
      static_cast<const b2CircleShape*>(physics_->pedestal->GetFixtureList()->GetShape());
  const b2Transform& xc = physics_->pedestal->GetTransform();
  for (size_t i = 0; i < sheep_.size(); ++i) {
    const b2Body* bi = sheep_[i]->body;
    const auto* pi = static_cast<const b2PolygonShape*>(bi->GetFixtureList()->GetShape());
    b2Manifold m;
    if (config_.pedestal) {  // otherwise sheep may pass through it
      b2CollidePolygonAndCircle(&m, pi, bi->GetTransform(), column, xc);
      measure(m, bi->GetTransform(), pi->m_radius, xc, column->m_radius);
    }
    if (!config_.sheep_collisions) continue;  // sheep may pass through each other
    for (size_t j = i + 1; j < sheep_.size(); ++j) {
      const b2Body* bj = sheep_[j]->body;
      const auto* pj = static_cast<const b2PolygonShape*>(bj->GetFixtureList()->GetShape());
      b2CollidePolygons(&m, pi, bi->GetTransform(), pj, bj->GetTransform());
      measure(m, bi->GetTransform(), pi->m_radius, bj->GetTransform(), pj->m_radius);
    }
  }
  return deepest;
}

}  // namespace ephor::sim
