#include "common/catch/sim/catch_scenario.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

namespace ephor::catching {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Camera pose draw (paper 000, section 3: the camera is placed anywhere the
// whole board face is in view).
constexpr double kCameraDistanceMinMm = 1200.0;
constexpr double kCameraDistanceMaxMm = 2000.0;
constexpr double kElevationMinDeg = 35.0;  // above the board plane
constexpr double kElevationMaxDeg = 80.0;
constexpr double kAimOffsetMm = 60.0;  // look-at point within this of the board centre (x, y of B)
constexpr double kRollMaxDeg = 15.0;
constexpr double kCameraMinHeightWMm = 300.0;  // above the table
// The arm works below the board's bottom edge; a camera is out of its way
// when x_W > 700 mm (over the board) or z_W > 900 mm (above the arm).
constexpr double kArmSpaceMaxXWMm = 700.0;
constexpr double kArmSpaceMaxZWMm = 900.0;
constexpr int kMaxCameraDraws = 100000;

constexpr double kFocalPx = 560.0;

// Distance from p to the segment a-b.
double segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                        const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

std::vector<Peg> draw_pegs(std::mt19937_64& rng, const BoardSpec& board, double incline_rad,
                           double peg_diameter_mm, double peg_height_mm) {
  const double rp = 0.5 * peg_diameter_mm;
  const double gap = board.ball_diameter_mm + kPegGapOverBallMm;
  const double x0 = rp + gap, x1 = board.width_mm - rp - gap;
  const double y0 = kPegFreeTopMm + rp, y1 = board.height_mm - kPegFreeBottomMm - rp;
  if (x1 <= x0 || y1 <= y0) throw std::invalid_argument("catch scenario: board too small for pegs");
  // The shadow of a peg under overhead light falls down the slope.
  const double shadow_mm = peg_height_mm * std::tan(incline_rad);
  std::uniform_int_distribution<int> count(kPegsMin, kPegsMax);
  std::uniform_real_distribution<double> ux(x0, x1), uy(y0, y1);
  const int n = count(rng);
  std::vector<Peg> pegs;
  for (int attempt = 0; attempt < 100000 && static_cast<int>(pegs.size()) < n; ++attempt) {
    const Peg p{ux(rng), uy(rng)};
    const Eigen::Vector2d c(p.x_mm, p.y_mm);
    bool ok = true;
    for (const Peg& q : pegs)
      ok = ok && std::hypot(p.x_mm - q.x_mm, p.y_mm - q.y_mm) >= 2.0 * rp + gap;
    for (const BoardCircle& circle : board.circles)
      ok = ok && segment_distance(Eigen::Vector2d(circle.x_mm, circle.y_mm), c,
                                  c + Eigen::Vector2d(0.0, shadow_mm)) >=
                     0.5 * circle.diameter_mm + rp + kPegCircleClearanceMm;
    if (ok) pegs.push_back(p);
  }
  if (static_cast<int>(pegs.size()) < n)
    throw std::invalid_argument("catch scenario: cannot place " + std::to_string(n) +
                                " pegs apart on the board");
  return pegs;
}

Lighting draw_lighting(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * u01(rng); };
  Lighting l;
  l.base_gain = uniform(0.8, 0.95);
  l.band_direction_rad = uniform(0.0, std::numbers::pi);
  const int n = u01(rng) < 0.5 ? 2 : 3;
  for (int k = 0; k < n; ++k)
    l.bands.push_back({uniform(-450.0, 450.0), uniform(40.0, 120.0), uniform(0.15, 0.35)});
  l.vignette = uniform(0.1, 0.25);
  return l;
}

Appearance draw_appearance(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  Appearance a;
  a.board_level = 110.0 + 20.0 * u01(rng);
  const double magnitude = 4.0 + 4.0 * u01(rng);
  a.ball_contrast = u01(rng) < 0.5 ? -magnitude : magnitude;
  return a;
}

// A camera looking from cam_b towards target_b (both in B), its image's down
// direction along the projection of `down_b` (W's gravity, so the horizon is
// level) turned by roll about the optical axis.
Pose look_at(const Eigen::Vector3d& cam_b, const Eigen::Vector3d& target_b,
             const Eigen::Vector3d& down_b, double roll_rad) {
  const Eigen::Vector3d z = (target_b - cam_b).normalized();
  Eigen::Vector3d y = down_b - down_b.dot(z) * z;
  // Looking straight down W's vertical: take the slope's direction instead.
  if (y.norm() < 0.1) y = Eigen::Vector3d::UnitY() - z.y() * z;
  y.normalize();
  const Eigen::Vector3d x = y.cross(z);
  const Eigen::AngleAxisd roll(roll_rad, z);
  Pose camera_to_board = Pose::Identity();
  camera_to_board.linear().col(0) = roll * x;
  camera_to_board.linear().col(1) = roll * y;
  camera_to_board.linear().col(2) = z;
  camera_to_board.translation() = cam_b;
  return camera_to_board.inverse();
}

}  // namespace

double Lighting::board_gain(double x_mm, double y_mm, const BoardSpec& board) const {
  // Signed distance across the bands, measured from the board centre.
  const double nx = -std::sin(band_direction_rad), ny = std::cos(band_direction_rad);
  const double across = (x_mm - 0.5 * board.width_mm) * nx + (y_mm - 0.5 * board.height_mm) * ny;
  double g = base_gain;
  for (const LightBand& b : bands) {
    const double d = (across - b.offset_mm) / b.width_mm;
    g += b.amplitude * std::exp(-0.5 * d * d);
  }
  return g;
}

CatchScenario CatchScenario::draw(uint64_t seed, const BoardSpec& board) {
  CatchScenario s;
  s.seed = seed;
  s.board = board;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * u01(rng); };

  s.placement.incline_rad = uniform(kInclineMinDeg, kInclineMaxDeg) * kDeg;
  s.pegs = draw_pegs(rng, s.board, s.placement.incline_rad, s.peg_diameter_mm, s.peg_height_mm);
  s.lighting = draw_lighting(rng);
  s.appearance = draw_appearance(rng);

  s.intrinsics = CameraIntrinsics{};
  s.intrinsics.fx = s.intrinsics.fy = kFocalPx;
  s.intrinsics.cx = 0.5 * (s.intrinsics.width - 1);
  s.intrinsics.cy = 0.5 * (s.intrinsics.height - 1);

  const Pose b2w = s.board_to_world();
  const Eigen::Vector3d down_b = b2w.linear().transpose() * Eigen::Vector3d(0.0, 0.0, -1.0);
  const Eigen::Vector3d centre_b(0.5 * board.width_mm, 0.5 * board.height_mm, 0.0);
  for (s.camera_draws = 1; s.camera_draws <= kMaxCameraDraws; ++s.camera_draws) {
    const double distance = uniform(kCameraDistanceMinMm, kCameraDistanceMaxMm);
    const double elevation = uniform(kElevationMinDeg, kElevationMaxDeg) * kDeg;
    const double azimuth = uniform(-std::numbers::pi, std::numbers::pi);
    const Eigen::Vector3d dir(std::cos(elevation) * std::cos(azimuth),
                              std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
    const Eigen::Vector3d cam_b = centre_b + distance * dir;
    const Eigen::Vector3d target_b =
        centre_b + Eigen::Vector3d(uniform(-kAimOffsetMm, kAimOffsetMm),
                                   uniform(-kAimOffsetMm, kAimOffsetMm), 0.0);
    const double roll = uniform(-kRollMaxDeg, kRollMaxDeg) * kDeg;
    s.board_to_camera = look_at(cam_b, target_b, down_b, roll);
    const Eigen::Vector3d cam_w = b2w * cam_b;
    const bool clear_of_arm = cam_w.x() > kArmSpaceMaxXWMm || cam_w.z() > kArmSpaceMaxZWMm;
    if (cam_w.z() > kCameraMinHeightWMm && clear_of_arm && s.corners_in_view(kCornerMarginPx))
      return s;
  }
  throw std::invalid_argument("catch scenario: no camera pose sees the whole board");
}

BallRelease CatchScenario::release(int k) const {
  std::seed_seq seq{static_cast<uint32_t>(seed), static_cast<uint32_t>(seed >> 32),
                    static_cast<uint32_t>(k), 0x8a11u};
  std::mt19937_64 rng(seq);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double r = board.ball_radius_mm();
  const double x0 = r + 40.0, x1 = board.width_mm - r - 40.0;
  BallRelease b;
  b.x_mm = x0 + (x1 - x0) * u01(rng);
  b.y_mm = r + 10.0;
  const double speed = 5.0 * u01(rng);               // mm/s
  const double angle = std::numbers::pi * u01(rng);  // 0..pi: never up the slope
  b.vx_mm_s = speed * std::cos(angle);
  b.vy_mm_s = speed * std::sin(angle);
  return b;
}

std::optional<Eigen::Vector2d> CatchScenario::project(const Eigen::Vector3d& p_b_mm) const {
  const Eigen::Vector3d p = board_to_camera * p_b_mm;
  if (p.z() <= 1.0) return std::nullopt;
  return Eigen::Vector2d(intrinsics.fx * p.x() / p.z() + intrinsics.cx,
                         intrinsics.fy * p.y() / p.z() + intrinsics.cy);
}

std::vector<Eigen::Vector2d> CatchScenario::measured_pegs() const {
  std::mt19937_64 rng(seed ^ 0x9e65ULL);
  std::normal_distribution<double> noise(0.0, kSurveyNoiseMm);
  std::vector<Eigen::Vector2d> out;
  for (const Peg& p : pegs) {
    const double x = p.x_mm + noise(rng);  // x first: the order of the draws is the seed's
    const double y = p.y_mm + noise(rng);
    out.emplace_back(x, y);
  }
  return out;
}

CatchScenario::TouchedPoints CatchScenario::touched_points() const {
  std::mt19937_64 rng(seed ^ 0x5eedULL);
  std::normal_distribution<double> noise(0.0, kSurveyNoiseMm);
  const Pose b2w = board_to_world();
  TouchedPoints out;
  out.board_mm = {Eigen::Vector2d(50.0, 50.0), Eigen::Vector2d(board.width_mm - 50.0, 50.0),
                  Eigen::Vector2d(board.width_mm / 2.0, board.height_mm - 50.0)};
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d w = b2w * Eigen::Vector3d(out.board_mm[i].x(), out.board_mm[i].y(), 0.0);
    for (int k = 0; k < 3; ++k) out.world_mm[i][k] = w[k] + noise(rng);
  }
  return out;
}

bool CatchScenario::corners_in_view(double margin_px) const {
  for (const double x : {0.0, board.width_mm}) {
    for (const double y : {0.0, board.height_mm}) {
      const auto uv = project(Eigen::Vector3d(x, y, 0.0));
      if (!uv) return false;
      if (uv->x() < margin_px || uv->x() > intrinsics.width - 1 - margin_px ||
          uv->y() < margin_px || uv->y() > intrinsics.height - 1 - margin_px)
        return false;
    }
  }
  return true;
}

}  // namespace ephor::catching
