#include "common/catch/sim/board_renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace ephor::catching {
namespace {

constexpr float kFar = std::numeric_limits<float>::infinity();
constexpr int kSupersample = 8;  // per axis, at edges of the static scene
constexpr size_t kNoiseTableSize = size_t{1} << 20;
constexpr double kTextureCellPx = 40.0;

// Materials of the static scene; a pixel whose corners see different ones is
// supersampled.
constexpr int kSurround = 0;
constexpr int kBoard = 1;
constexpr int kCircle = 2;       // + circle index
constexpr int kPeg = 10;         // + peg index
constexpr int kShadow = 100000;  // + peg index

constexpr double kPegSideShade = 0.7;  // peg side relative to its top
constexpr double kArmLevel = 35.0;
constexpr double kCupLevel = 45.0;
constexpr double kCupInsideLevel = 15.0;
constexpr double kCupWallMm = 3.0;

// Range along the unit ray `d` from the origin to capsule a-b of radius r;
// negative: missed (after Inigo Quilez's capsule intersection).
double ray_capsule(const Eigen::Vector3d& d, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                   double r) {
  const Eigen::Vector3d ba = b - a, oa = -a;
  const double baba = ba.dot(ba), bard = ba.dot(d), baoa = ba.dot(oa), rdoa = d.dot(oa),
               oaoa = oa.dot(oa);
  const double qa = baba - bard * bard;
  const double qb = baba * rdoa - baoa * bard;
  const double qc = baba * oaoa - baoa * baoa - r * r * baba;
  const double h = qb * qb - qa * qc;
  if (h < 0.0) return -1.0;
  if (qa > 1e-9) {
    const double t = (-qb - std::sqrt(h)) / qa;
    const double y = baoa + t * bard;
    if (y > 0.0 && y < baba) return t;
    const Eigen::Vector3d oc = y <= 0.0 ? oa : Eigen::Vector3d(-b);
    const double cb = d.dot(oc), cc = oc.dot(oc) - r * r, ch = cb * cb - cc;
    return ch > 0.0 ? -cb - std::sqrt(ch) : -1.0;
  }
  // Ray parallel to the axis: the nearer end sphere.
  double best = -1.0;
  for (const Eigen::Vector3d& e : {a, b}) {
    const double cb = -d.dot(e), cc = e.dot(e) - r * r, ch = cb * cb - cc;
    if (ch > 0.0) {
      const double t = -cb - std::sqrt(ch);
      if (t > 0.0 && (best < 0.0 || t < best)) best = t;
    }
  }
  return best;
}

}  // namespace

BoardRenderer::BoardRenderer(const CatchScenario& scenario, CupSpec cup, uint64_t noise_seed)
    : scenario_(scenario),
      intrinsics_(scenario.intrinsics),
      cup_(cup),
      world_to_camera_(scenario.world_to_camera()),
      camera_to_board_(scenario.board_to_camera.inverse()),
      rng_(noise_seed) {
  if (intrinsics_.width <= 0 || intrinsics_.height <= 0 || intrinsics_.width > 4096 ||
      intrinsics_.height > 4096 || !(intrinsics_.fx > 0.0) || !(intrinsics_.fy > 0.0))
    throw std::invalid_argument("board renderer: image size must be 1..4096 px and fx, fy > 0");
  if (!(scenario_.appearance.noise_sigma >= 0.0))
    throw std::invalid_argument("board renderer: noise_sigma must be >= 0");
  light_c_ = world_to_camera_.linear() * Eigen::Vector3d::UnitZ();
  shadow_length_mm_ = scenario_.peg_height_mm * std::tan(scenario_.placement.incline_rad);

  // Where each peg can appear in the image: its bounding box's projection.
  const double rp = 0.5 * scenario_.peg_diameter_mm;
  for (const Peg& p : scenario_.pegs) {
    double u0 = 1e9, v0 = 1e9, u1 = -1e9, v1 = -1e9;
    for (const double dx : {-rp, rp})
      for (const double dy : {-rp, rp})
        for (const double z : {0.0, scenario_.peg_height_mm}) {
          const auto uv = scenario_.project(Eigen::Vector3d(p.x_mm + dx, p.y_mm + dy, z));
          if (!uv) continue;
          u0 = std::min(u0, uv->x()), u1 = std::max(u1, uv->x());
          v0 = std::min(v0, uv->y()), v1 = std::max(v1, uv->y());
        }
    peg_boxes_.push_back({static_cast<int>(std::floor(u0)) - 1,
                          static_cast<int>(std::floor(v0)) - 1, static_cast<int>(std::ceil(u1)) + 1,
                          static_cast<int>(std::ceil(v1)) + 1});
  }

  // The lab's texture: a coarse random grid, interpolated.
  std::mt19937_64 tex_rng(scenario_.seed ^ 0x7e47u);
  std::uniform_real_distribution<float> u11(-1.0f, 1.0f);
  texture_cols_ = static_cast<int>(intrinsics_.width / kTextureCellPx) + 2;
  const int rows = static_cast<int>(intrinsics_.height / kTextureCellPx) + 2;
  texture_.resize(static_cast<size_t>(texture_cols_ * rows));
  for (float& t : texture_) t = u11(tex_rng);

  render_background();

  std::normal_distribution<float> n01(0.0f, 1.0f);
  std::mt19937_64 noise_rng(noise_seed ^ 0x9e3779b97f4a7c15ULL);
  const size_t n = static_cast<size_t>(width()) * static_cast<size_t>(height());
  noise_table_.resize(std::max(kNoiseTableSize, 2 * n));
  const auto sigma = static_cast<float>(scenario_.appearance.noise_sigma);
  for (float& x : noise_table_) x = sigma * n01(noise_rng);
}

Eigen::Vector3d BoardRenderer::ray(double u, double v) const {
  return Eigen::Vector3d((u - intrinsics_.cx) / intrinsics_.fx,
                         (v - intrinsics_.cy) / intrinsics_.fy, 1.0)
      .normalized();
}

BoardRenderer::Sample BoardRenderer::sample(double u, double v) const {
  const Appearance& look = scenario_.appearance;
  const BoardSpec& board = scenario_.board;
  const double du = (u - intrinsics_.cx) / (0.5 * intrinsics_.width);
  const double dv = (v - intrinsics_.cy) / (0.5 * intrinsics_.height);
  const double vignette = 1.0 - scenario_.lighting.vignette * 0.5 * (du * du + dv * dv);
  const Eigen::Vector3d o = camera_to_board_.translation();
  const Eigen::Vector3d d = camera_to_board_.linear() * ray(u, v);

  // Pegs: capped cylinders standing on the face.
  const double rp = 0.5 * scenario_.peg_diameter_mm, hp = scenario_.peg_height_mm;
  double best_t = kFar;
  int best_peg = -1;
  bool best_top = false;
  const int iu = static_cast<int>(std::lround(u)), iv = static_cast<int>(std::lround(v));
  for (size_t j = 0; j < scenario_.pegs.size(); ++j) {
    const PegBox& box = peg_boxes_[j];
    if (iu < box.u0 || iu > box.u1 || iv < box.v0 || iv > box.v1) continue;
    const Eigen::Vector2d c(scenario_.pegs[j].x_mm, scenario_.pegs[j].y_mm);
    if (d.z() < 0.0) {
      const double t = (hp - o.z()) / d.z();
      if (t > 0.0 && (o.head<2>() + t * d.head<2>() - c).norm() <= rp && t < best_t)
        best_t = t, best_peg = static_cast<int>(j), best_top = true;
    }
    const Eigen::Vector2d oc = o.head<2>() - c, d2 = d.head<2>();
    const double a = d2.dot(d2), b = oc.dot(d2), cc = oc.dot(oc) - rp * rp;
    const double disc = b * b - a * cc;
    if (a > 1e-12 && disc >= 0.0) {
      const double t = (-b - std::sqrt(disc)) / a;
      const double z = o.z() + t * d.z();
      if (t > 0.0 && z >= 0.0 && z <= hp && t < best_t)
        best_t = t, best_peg = static_cast<int>(j), best_top = false;
    }
  }
  if (best_peg >= 0) {
    const Peg& p = scenario_.pegs[static_cast<size_t>(best_peg)];
    const double g = look.peg_level * scenario_.lighting.board_gain(p.x_mm, p.y_mm, board) *
                     (best_top ? 1.0 : kPegSideShade) * vignette;
    return {static_cast<float>(g), static_cast<float>(best_t), kPeg + best_peg};
  }

  if (d.z() < 0.0) {
    const double t = -o.z() / d.z();
    const double x = o.x() + t * d.x(), y = o.y() + t * d.y();
    if (board.on_board(x, y)) {
      const double gain = scenario_.lighting.board_gain(x, y, board) * vignette;
      for (size_t k = 0; k < board.circles.size(); ++k) {
        const BoardCircle& c = board.circles[k];
        if (std::hypot(x - c.x_mm, y - c.y_mm) <= 0.5 * c.diameter_mm)
          return {static_cast<float>(look.circle_level * gain), static_cast<float>(t),
                  kCircle + static_cast<int>(k)};
      }
      for (size_t j = 0; j < scenario_.pegs.size(); ++j) {
        const Peg& p = scenario_.pegs[j];
        // Within rp of the segment from the peg's foot down the slope.
        const double sy = std::clamp(y - p.y_mm, 0.0, shadow_length_mm_);
        if (std::hypot(x - p.x_mm, y - p.y_mm - sy) <= rp)
          return {static_cast<float>(look.board_level * look.shadow_factor * gain),
                  static_cast<float>(t), kShadow + static_cast<int>(j)};
      }
      return {static_cast<float>(look.board_level * gain), static_cast<float>(t), kBoard};
    }
  }
  // The lab beyond the board.
  const double tu = std::clamp(u / kTextureCellPx, 0.0, texture_cols_ - 1.001);
  const int rows = static_cast<int>(texture_.size()) / texture_cols_;
  const double tv = std::clamp(v / kTextureCellPx, 0.0, rows - 1.001);
  const int cu = static_cast<int>(tu), cv = static_cast<int>(tv);
  const double fu = tu - cu, fv = tv - cv;
  auto at = [&](int c, int r) {
    return static_cast<double>(texture_[static_cast<size_t>(r * texture_cols_ + c)]);
  };
  const double tex = (1.0 - fv) * ((1.0 - fu) * at(cu, cv) + fu * at(cu + 1, cv)) +
                     fv * ((1.0 - fu) * at(cu, cv + 1) + fu * at(cu + 1, cv + 1));
  return {static_cast<float>((look.surround_level + look.surround_texture * tex) * vignette), kFar,
          kSurround};
}

void BoardRenderer::render_background() {
  const int w = width(), h = height();
  background_.create(h, w, CV_32FC1);
  board_level_.create(h, w, CV_32FC1);
  depth_.create(h, w, CV_32FC1);
  // Materials at the pixel corners (u - 0.5, v - 0.5).
  std::vector<int> corner(static_cast<size_t>((w + 1) * (h + 1)));
  for (int v = 0; v <= h; ++v)
    for (int u = 0; u <= w; ++u)
      corner[static_cast<size_t>(v * (w + 1) + u)] = sample(u - 0.5, v - 0.5).material;

  const Eigen::Vector3d o = camera_to_board_.translation();
  for (int v = 0; v < h; ++v) {
    float* bg = background_.ptr<float>(v);
    float* lvl = board_level_.ptr<float>(v);
    float* dep = depth_.ptr<float>(v);
    for (int u = 0; u < w; ++u) {
      const Sample s = sample(u, v);
      const auto c = [&](int du, int dv) {
        return corner[static_cast<size_t>((v + dv) * (w + 1) + u + du)];
      };
      float grey = s.grey;
      if (c(0, 0) != s.material || c(1, 0) != s.material || c(0, 1) != s.material ||
          c(1, 1) != s.material) {
        double sum = 0.0;
        for (int j = 0; j < kSupersample; ++j)
          for (int i = 0; i < kSupersample; ++i)
            sum += static_cast<double>(
                sample(u - 0.5 + (i + 0.5) / kSupersample, v - 0.5 + (j + 0.5) / kSupersample)
                    .grey);
        grey = static_cast<float>(sum / (kSupersample * kSupersample));
      }
      bg[u] = grey;
      dep[u] = s.depth;
      // The lit face's level here, as if the board plane went on forever.
      const double du = (u - intrinsics_.cx) / (0.5 * w), dv = (v - intrinsics_.cy) / (0.5 * h);
      const double vignette = 1.0 - scenario_.lighting.vignette * 0.5 * (du * du + dv * dv);
      const Eigen::Vector3d d = camera_to_board_.linear() * ray(u, v);
      double gain = scenario_.lighting.base_gain;
      if (d.z() < 0.0) {
        const double t = -o.z() / d.z();
        gain = scenario_.lighting.board_gain(o.x() + t * d.x(), o.y() + t * d.y(), scenario_.board);
      }
      lvl[u] = static_cast<float>(scenario_.appearance.board_level * gain * vignette);
    }
  }
}

std::optional<Eigen::Vector2d> BoardRenderer::ball_image_position(
    const Eigen::Vector3d& ball_b_mm) const {
  return scenario_.project(ball_b_mm);
}

void BoardRenderer::draw_ball(const Eigen::Vector3d& ball_b_mm, cv::Mat& depth, bool write_depth) {
  const Eigen::Vector3d pc = scenario_.board_to_camera * ball_b_mm;
  const double r = scenario_.board.ball_radius_mm();
  if (pc.z() <= r + 10.0) return;
  const double uc = intrinsics_.fx * pc.x() / pc.z() + intrinsics_.cx;
  const double vc = intrinsics_.fy * pc.y() / pc.z() + intrinsics_.cy;
  // Off-axis spheres project as ellipses stretched radially: a generous box.
  const double reach = 1.6 * std::max(intrinsics_.fx, intrinsics_.fy) * r / (pc.z() - r) + 2.0;
  const int u0 = std::max(0, static_cast<int>(std::floor(uc - reach)));
  const int u1 = std::min(width() - 1, static_cast<int>(std::ceil(uc + reach)));
  const int v0 = std::max(0, static_cast<int>(std::floor(vc - reach)));
  const int v1 = std::min(height() - 1, static_cast<int>(std::ceil(vc + reach)));
  const double contrast = scenario_.appearance.ball_contrast;
  const double pc2 = pc.squaredNorm();
  const double px_per_mm = std::min(intrinsics_.fx, intrinsics_.fy);
  for (int v = v0; v <= v1; ++v) {
    float* row = scene_.ptr<float>(v);
    float* dep = depth.ptr<float>(v);
    const float* lvl = board_level_.ptr<float>(v);
    for (int u = u0; u <= u1; ++u) {
      const Eigen::Vector3d d = ray(u, v);
      const double along = d.dot(pc);
      const double dist = std::sqrt(std::max(0.0, pc2 - along * along));
      const double pixel_mm = along / px_per_mm;  // one pixel's width at the ball
      const double cover = std::clamp((r - dist) / pixel_mm + 0.5, 0.0, 1.0);
      if (cover <= 0.0) continue;
      const double t = along - std::sqrt(std::max(0.0, r * r - dist * dist));
      if (t >= static_cast<double>(dep[u])) continue;  // a peg or the arm is in front
      const Eigen::Vector3d normal = (t * d - pc) / r;
      const double shade = 0.55 + 0.45 * std::max(0.0, normal.dot(light_c_));
      const double grey = static_cast<double>(lvl[u]) + contrast * shade;
      row[u] += static_cast<float>(cover * (grey - static_cast<double>(row[u])));
      if (write_depth && cover >= 0.5) dep[u] = static_cast<float>(t);
    }
  }
}

void BoardRenderer::draw_capsule(const Capsule& c, cv::Mat& depth) {
  const Eigen::Vector3d a = world_to_camera_ * c.a_w_mm, b = world_to_camera_ * c.b_w_mm;
  const double r = c.radius_mm;
  const double zmin = std::min(a.z(), b.z()) - r;
  if (zmin <= 10.0 || !(r > 0.0)) return;  // behind or at the camera: not drawn
  double umin = 1e9, umax = -1e9, vmin = 1e9, vmax = -1e9;
  for (const Eigen::Vector3d& e : {a, b}) {
    const double u = intrinsics_.fx * e.x() / e.z() + intrinsics_.cx;
    const double v = intrinsics_.fy * e.y() / e.z() + intrinsics_.cy;
    umin = std::min(umin, u), umax = std::max(umax, u), vmin = std::min(vmin, v),
    vmax = std::max(vmax, v);
  }
  const double reach = 1.6 * std::max(intrinsics_.fx, intrinsics_.fy) * r / zmin + 2.0;
  const int u0 = std::max(0, static_cast<int>(std::floor(umin - reach)));
  const int u1 = std::min(width() - 1, static_cast<int>(std::ceil(umax + reach)));
  const int v0 = std::max(0, static_cast<int>(std::floor(vmin - reach)));
  const int v1 = std::min(height() - 1, static_cast<int>(std::ceil(vmax + reach)));
  const Eigen::Vector3d ba = b - a;
  const double baba = std::max(ba.squaredNorm(), 1e-12);
  for (int v = v0; v <= v1; ++v) {
    float* row = scene_.ptr<float>(v);
    float* dep = depth.ptr<float>(v);
    for (int u = u0; u <= u1; ++u) {
      const Eigen::Vector3d d = ray(u, v);
      const double t = ray_capsule(d, a, b, r);
      if (t <= 0.0 || t >= static_cast<double>(dep[u])) continue;
      const Eigen::Vector3d p = t * d;
      const Eigen::Vector3d q = a + std::clamp((p - a).dot(ba) / baba, 0.0, 1.0) * ba;
      const double shade = 0.6 + 0.4 * std::max(0.0, (p - q).dot(light_c_) / r);
      row[u] = static_cast<float>(kArmLevel * shade);
      dep[u] = static_cast<float>(t);
    }
  }
}

void BoardRenderer::draw_cup(const Eigen::Vector3d& opening_w_mm, cv::Mat& depth) {
  // A capped cylinder from the opening down depth_mm; the top cap is the
  // opening (the cup's dark inside).
  const Eigen::Vector3d top = world_to_camera_ * opening_w_mm;
  const Eigen::Vector3d bottom =
      world_to_camera_ * (opening_w_mm - Eigen::Vector3d(0.0, 0.0, cup_.depth_mm));
  const double r = cup_.inner_radius_mm + kCupWallMm;
  const double zmin = std::min(top.z(), bottom.z()) - r;
  if (zmin <= 10.0) return;
  double umin = 1e9, umax = -1e9, vmin = 1e9, vmax = -1e9;
  for (const Eigen::Vector3d& e : {top, bottom}) {
    const double u = intrinsics_.fx * e.x() / e.z() + intrinsics_.cx;
    const double v = intrinsics_.fy * e.y() / e.z() + intrinsics_.cy;
    umin = std::min(umin, u), umax = std::max(umax, u), vmin = std::min(vmin, v),
    vmax = std::max(vmax, v);
  }
  const double reach = 1.6 * std::max(intrinsics_.fx, intrinsics_.fy) * r / zmin + 2.0;
  const int u0 = std::max(0, static_cast<int>(std::floor(umin - reach)));
  const int u1 = std::min(width() - 1, static_cast<int>(std::ceil(umax + reach)));
  const int v0 = std::max(0, static_cast<int>(std::floor(vmin - reach)));
  const int v1 = std::min(height() - 1, static_cast<int>(std::ceil(vmax + reach)));
  // Axis from the opening (pa) down to the bottom (pb) (Inigo Quilez's capped cylinder).
  const Eigen::Vector3d ba = bottom - top, oc = -top;
  const double baba = ba.dot(ba), baoc = ba.dot(oc);
  for (int v = v0; v <= v1; ++v) {
    float* row = scene_.ptr<float>(v);
    float* dep = depth.ptr<float>(v);
    for (int u = u0; u <= u1; ++u) {
      const Eigen::Vector3d d = ray(u, v);
      const double bard = ba.dot(d);
      const double k2 = baba - bard * bard;
      const double k1 = baba * oc.dot(d) - baoc * bard;
      const double k0 = baba * oc.dot(oc) - baoc * baoc - r * r * baba;
      double h = k1 * k1 - k2 * k0;
      if (h < 0.0 || k2 < 1e-9) continue;
      h = std::sqrt(h);
      double t = (-k1 - h) / k2;
      const double y = baoc + t * bard;
      double grey = 0.0;
      if (y > 0.0 && y < baba) {
        const Eigen::Vector3d n = (oc + t * d - ba * y / baba) / r;
        grey = kCupLevel * (0.6 + 0.4 * std::max(0.0, n.dot(light_c_)));
      } else {
        t = ((y < 0.0 ? 0.0 : baba) - baoc) / bard;
        if (std::abs(k1 + k2 * t) >= h) continue;
        grey = y < 0.0 ? kCupInsideLevel : kCupLevel * 0.6;
      }
      if (t <= 0.0 || t >= static_cast<double>(dep[u])) continue;
      row[u] = static_cast<float>(grey);
      dep[u] = static_cast<float>(t);
    }
  }
}

std::optional<Eigen::Vector2d> BoardRenderer::render(
    const std::optional<Eigen::Vector3d>& ball_b_mm, const ArmView& arm, cv::Mat& image) {
  background_.copyTo(scene_);
  // The depth buffer is copied only when the arm may be drawn over the ball.
  const bool arm_in_view = !arm.links_w.empty() || arm.cup_opening_w_mm.has_value();
  if (arm_in_view) depth_.copyTo(frame_depth_);
  cv::Mat& depth = arm_in_view ? frame_depth_ : depth_;
  std::optional<Eigen::Vector2d> ball_px;
  if (ball_b_mm) {
    ball_px = ball_image_position(*ball_b_mm);
    draw_ball(*ball_b_mm, depth, arm_in_view);
  }
  for (const Capsule& c : arm.links_w) draw_capsule(c, depth);
  if (arm.cup_opening_w_mm) draw_cup(*arm.cup_opening_w_mm, depth);

  image.create(height(), width(), CV_8UC1);
  const size_t n = static_cast<size_t>(width()) * static_cast<size_t>(height());
  std::uniform_int_distribution<size_t> offset(0, noise_table_.size() - n);
  const float* noise = noise_table_.data() + offset(rng_);
  const float* src = scene_.ptr<float>(0);
  uint8_t* dst = image.ptr<uint8_t>(0);
  for (size_t i = 0; i < n; ++i) {
    const float g = std::clamp(src[i] + noise[i] + 0.5f, 0.0f, 255.0f);
    dst[i] = static_cast<uint8_t>(g);
  }
  return ball_px;
}

}  // namespace ephor::catching
