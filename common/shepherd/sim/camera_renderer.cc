#include "common/shepherd/sim/camera_renderer.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace ephor::sim {
namespace {

constexpr size_t kNoiseTableSize = size_t{1} << 20;  // > 4 frames of 512 x 482 samples

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("sim camera config: " + what);
}

bool level_ok(double g) { return std::isfinite(g) && g >= 0.0 && g <= 255.0; }

// Coverage of a pixel whose centre lies `d` px inside an edge (negative:
// outside): a one-pixel linear ramp centred on the edge.
inline float coverage(double d) { return static_cast<float>(std::clamp(d + 0.5, 0.0, 1.0)); }

inline void blend(float& px, float level, float c) { px += c * (level - px); }

}  // namespace

void validate(const CameraConfig& c) {
  require(c.camera.width_px > 0 && c.camera.height_px > 0 && c.camera.width_px <= 4096 &&
              c.camera.height_px <= 4096,
          "image size must be in 1..4096 px");
  require(std::isfinite(c.camera.focal_px) && c.camera.focal_px > 0.0, "focal_px must be > 0");
  require(std::isfinite(c.camera.height_mm) && c.camera.height_mm > 300.0,
          "camera height_mm must be > 300");
  require(level_ok(c.surround_level) && level_ok(c.field_level) && level_ok(c.body_level) &&
              level_ok(c.arm_level) && level_ok(c.mark_level),
          "grey levels must be in [0, 255]");
  require(std::isfinite(c.noise_sigma) && c.noise_sigma >= 0.0 && c.noise_sigma <= 50.0,
          "noise_sigma must be in [0, 50]");
  require(std::isfinite(c.gain_gradient) && c.gain_gradient >= 0.0 && c.gain_gradient < 0.5,
          "gain_gradient must be in [0, 0.5)");
  require(std::isfinite(c.gain_direction_rad), "gain_direction_rad must be finite");
  require(std::isfinite(c.vignette) && c.vignette >= 0.0 && c.vignette < 0.5,
          "vignette must be in [0, 0.5)");
  require(c.max_hidden_fraction > 0.0 && c.max_hidden_fraction <= 1.0,
          "max_hidden_fraction must be in (0, 1]");
}

CameraRenderer::CameraRenderer(CameraConfig config, const WorldConfig& world)
    : config_(std::move(config)), world_(world), rng_(config_.seed) {
  validate(config_);
  validate(world_);
  const int w = width(), h = height();
  const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h);
  const auto& cam = config_.camera;

  // Lighting: linear ramp reaching +-gain_gradient at the corners, times a
  // quadratic vignette.
  gain_.resize(n);
  const double half_diag = std::hypot(0.5 * w, 0.5 * h);
  const Eigen::Vector2d dir(std::cos(config_.gain_direction_rad),
                            std::sin(config_.gain_direction_rad));
  double max_proj = 0.0;
  for (const double su : {-0.5, 0.5})
    for (const double sv : {-0.5, 0.5})
      max_proj = std::max(max_proj, std::abs(su * w * dir.x() + sv * h * dir.y()));
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const double du = u - cam.cu_px, dv = v - cam.cv_px;
      const double ramp = config_.gain_gradient * (du * dir.x() + dv * dir.y()) / max_proj;
      const double r2 = (du * du + dv * dv) / (half_diag * half_diag);
      gain_[static_cast<size_t>(v) * static_cast<size_t>(w) + static_cast<size_t>(u)] =
          static_cast<float>((1.0 + ramp) * (1.0 - config_.vignette * r2));
    }
  }

  // The table top (the field) over darker surroundings.
  background_.assign(n, static_cast<float>(config_.surround_level));
  const auto& cell = world_.workcell;
  std::vector<Eigen::Vector2d> field = {cam.project(0.0, 0.0, 0.0),
                                        cam.project(cell.field_length_mm, 0.0, 0.0),
                                        cam.project(cell.field_length_mm, cell.field_width_mm, 0.0),
                                        cam.project(0.0, cell.field_width_mm, 0.0)};
  blend_convex(field, config_.field_level, background_);

  std::normal_distribution<float> n01(0.0f, 1.0f);
  std::mt19937_64 noise_rng(config_.seed ^ 0x9e3779b97f4a7c15ULL);
  noise_table_.resize(std::max(kNoiseTableSize, 2 * n));
  for (float& x : noise_table_) x = n01(noise_rng);
}

CameraRenderer::Capsule2 CameraRenderer::project(const ArmPart& part) const {
  const auto& cam = config_.camera;
  // Clamp heights below the camera so a bad pose cannot divide by zero.
  const double zmax = cam.height_mm - 100.0;
  const double za = std::min(part.a_mm.z(), zmax), zb = std::min(part.b_mm.z(), zmax);
  return {cam.project(part.a_mm.x(), part.a_mm.y(), za),
          cam.project(part.b_mm.x(), part.b_mm.y(), zb), part.radius_mm * cam.px_per_mm(za),
          part.radius_mm * cam.px_per_mm(zb)};
}

namespace {

// Closest-point parameter and interpolated radius of a (tapered) capsule:
// returns how far p lies inside its outline, px (negative outside).
double capsule_depth(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double ra, double rb,
                     const Eigen::Vector2d& p) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 1e-12 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return ra + t * (rb - ra) - (p - (a + t * ab)).norm();
}

}  // namespace

bool CameraRenderer::covers(const Capsule2& c, const Eigen::Vector2d& p) {
  return capsule_depth(c.a, c.b, c.ra, c.rb, p) > 0.0;
}

void CameraRenderer::blend_cloud(const Cloud& cloud) {
  const int w = width(), h = height();
  const double r = std::max(cloud.semi_u_px, cloud.semi_v_px);
  const int u0 = std::max(0, static_cast<int>(std::floor(cloud.centre_px.x() - r)));
  const int u1 = std::min(w - 1, static_cast<int>(std::ceil(cloud.centre_px.x() + r)));
  const int v0 = std::max(0, static_cast<int>(std::floor(cloud.centre_px.y() - r)));
  const int v1 = std::min(h - 1, static_cast<int>(std::ceil(cloud.centre_px.y() + r)));
  for (int v = v0; v <= v1; ++v) {
    for (int u = u0; u <= u1; ++u) {
      const double a = cloud.weight({u, v});  // pixel centres at integers, as blend_disc
      if (a <= 0.0) continue;
      float& g = scene_[static_cast<size_t>(v) * static_cast<size_t>(w) + static_cast<size_t>(u)];
      g = static_cast<float>((1.0 - a) * static_cast<double>(g) + a * cloud.level);
    }
  }
}

void CameraRenderer::blend_disc(const Eigen::Vector2d& centre, double radius, double level) {
  const int w = width(), h = height();
  const int u0 = std::max(0, static_cast<int>(std::floor(centre.x() - radius - 1.0)));
  const int u1 = std::min(w - 1, static_cast<int>(std::ceil(centre.x() + radius + 1.0)));
  const int v0 = std::max(0, static_cast<int>(std::floor(centre.y() - radius - 1.0)));
  const int v1 = std::min(h - 1, static_cast<int>(std::ceil(centre.y() + radius + 1.0)));
  const float lv = static_cast<float>(level);
  for (int v = v0; v <= v1; ++v) {
    float* row = scene_.data() + static_cast<size_t>(v) * static_cast<size_t>(w);
    const double dv = v - centre.y();
    for (int u = u0; u <= u1; ++u) {
      const double du = u - centre.x();
      const float c = coverage(radius - std::sqrt(du * du + dv * dv));
      if (c > 0.0f) blend(row[u], lv, c);
    }
  }
}

void CameraRenderer::blend_convex(const std::vector<Eigen::Vector2d>& poly, double level,
                                  std::vector<float>& target) const {
  const int w = width(), h = height();
  const size_t n = poly.size();
  // Inward unit normals, whatever the winding.
  double area2 = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const auto& p = poly[i];
    const auto& q = poly[(i + 1) % n];
    area2 += p.x() * q.y() - q.x() * p.y();
  }
  const double sign = area2 >= 0.0 ? 1.0 : -1.0;
  std::vector<Eigen::Vector2d> normals(n);
  std::vector<double> offsets(n);
  double umin = 1e9, umax = -1e9, vmin = 1e9, vmax = -1e9;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d e = poly[(i + 1) % n] - poly[i];
    normals[i] = sign * Eigen::Vector2d(-e.y(), e.x()).normalized();
    offsets[i] = normals[i].dot(poly[i]);
    umin = std::min(umin, poly[i].x()), umax = std::max(umax, poly[i].x());
    vmin = std::min(vmin, poly[i].y()), vmax = std::max(vmax, poly[i].y());
  }
  const int u0 = std::max(0, static_cast<int>(std::floor(umin - 1.0)));
  const int u1 = std::min(w - 1, static_cast<int>(std::ceil(umax + 1.0)));
  const int v0 = std::max(0, static_cast<int>(std::floor(vmin - 1.0)));
  const int v1 = std::min(h - 1, static_cast<int>(std::ceil(vmax + 1.0)));
  const float lv = static_cast<float>(level);
  for (int v = v0; v <= v1; ++v) {
    float* row = target.data() + static_cast<size_t>(v) * static_cast<size_t>(w);
    for (int u = u0; u <= u1; ++u) {
      const Eigen::Vector2d p(u, v);
      double depth = 1e9;
      for (size_t i = 0; i < n; ++i) depth = std::min(depth, normals[i].dot(p) - offsets[i]);
      const float c = coverage(depth);
      if (c > 0.0f) blend(row[u], lv, c);
    }
  }
}

void CameraRenderer::blend_capsule(const Capsule2& c, double level) {
  const int w = width(), h = height();
  const double r = std::max(c.ra, c.rb) + 1.0;
  const int u0 = std::max(0, static_cast<int>(std::floor(std::min(c.a.x(), c.b.x()) - r)));
  const int u1 = std::min(w - 1, static_cast<int>(std::ceil(std::max(c.a.x(), c.b.x()) + r)));
  const int v0 = std::max(0, static_cast<int>(std::floor(std::min(c.a.y(), c.b.y()) - r)));
  const int v1 = std::min(h - 1, static_cast<int>(std::ceil(std::max(c.a.y(), c.b.y()) + r)));
  const float lv = static_cast<float>(level);
  const Eigen::Vector2d ab = c.b - c.a;
  for (int v = v0; v <= v1; ++v) {
    float* row = scene_.data() + static_cast<size_t>(v) * static_cast<size_t>(w);
    // Where row v can meet the capsule: the hull of the two end discs and the
    // band within r of the segment's line (a superset of the capsule), so a
    // long diagonal link does not cost its whole bounding box.
    double lo = u1 + 1.0, hi = u0 - 1.0;
    auto take = [&](double from, double to) {
      lo = std::min(lo, from);
      hi = std::max(hi, to);
    };
    for (const Eigen::Vector2d& end : {c.a, c.b}) {
      const double dy = v - end.y();
      if (std::abs(dy) <= r) {
        const double half = std::sqrt(r * r - dy * dy);
        take(end.x() - half, end.x() + half);
      }
    }
    if (std::abs(ab.y()) > 1e-9) {  // within r of the segment's line
      const double uc = c.a.x() + (v - c.a.y()) / ab.y() * ab.x();
      const double half = r * ab.norm() / std::abs(ab.y());
      take(uc - half, uc + half);
    } else {
      take(u0, u1);
    }
    const int from = std::max(u0, static_cast<int>(std::floor(lo)));
    const int to = std::min(u1, static_cast<int>(std::ceil(hi)));
    for (int u = from; u <= to; ++u) {
      const float cov = coverage(capsule_depth(c.a, c.b, c.ra, c.rb, Eigen::Vector2d(u, v)));
      if (cov > 0.0f) blend(row[u], lv, cov);
    }
  }
}

std::vector<MarkView> CameraRenderer::mark_views(const std::vector<SheepState>& sheep,
                                                 const std::vector<ArmPart>& arm) const {
  const auto& cam = config_.camera;
  std::vector<Capsule2> parts;
  parts.reserve(arm.size());
  for (const auto& p : arm) parts.push_back(project(p));
  const double z = world_.mark_height_mm;
  const double radius = 0.5 * world_.mark_diameter_mm * cam.px_per_mm(z);

  // Area samples of a unit disc: centre and three rings (equal-area weights).
  static const std::vector<Eigen::Vector2d> samples = [] {
    std::vector<Eigen::Vector2d> s;
    const int rings[] = {6, 12, 18};
    s.emplace_back(0.0, 0.0);
    for (int k = 0; k < 3; ++k) {
      const double r = std::sqrt((k + 0.5) / 3.0);
      for (int i = 0; i < rings[k]; ++i) {
        const double a = 2.0 * std::numbers::pi * (i + 0.5 * k) / rings[k];
        s.emplace_back(r * std::cos(a), r * std::sin(a));
      }
    }
    return s;
  }();

  std::vector<MarkView> views;
  views.reserve(sheep.size());
  for (const auto& s : sheep) {
    MarkView mv;
    mv.id = s.id;
    mv.centre_px = cam.project(s.centre_mm.x(), s.centre_mm.y(), z);
    mv.radius_px = radius;
    int hidden = 0;
    for (const auto& unit : samples) {
      const Eigen::Vector2d p = mv.centre_px + radius * unit;
      for (const auto& c : parts) {
        if (covers(c, p)) {
          ++hidden;
          break;
        }
      }
    }
    mv.hidden_fraction = static_cast<double>(hidden) / static_cast<double>(samples.size());
    mv.visible = mv.hidden_fraction < config_.max_hidden_fraction;
    views.push_back(mv);
  }
  return views;
}

std::vector<MarkView> CameraRenderer::render(const std::vector<SheepState>& sheep,
                                             const std::vector<ArmPart>& arm,
                                             std::vector<uint8_t>& image, const ToolLight* light,
                                             const std::vector<Cloud>& clouds) {
  const auto& cam = config_.camera;
  scene_ = background_;
  // Bodies first (footprint of the body's top at body height), then the marks.
  const double hl = 0.5 * world_.body_length_mm, hw = 0.5 * world_.body_width_mm;
  std::vector<Eigen::Vector2d> corners(4);
  for (const auto& s : sheep) {
    const double c = std::cos(s.body_angle_rad), sn = std::sin(s.body_angle_rad);
    const double lx[] = {hl, -hl, -hl, hl}, ly[] = {hw, hw, -hw, -hw};
    for (int i = 0; i < 4; ++i)
      corners[static_cast<size_t>(i)] =
          cam.project(s.centre_mm.x() + c * lx[i] - sn * ly[i],
                      s.centre_mm.y() + sn * lx[i] + c * ly[i], world_.body_height_mm);
    blend_convex(corners, config_.body_level, scene_);
  }
  std::vector<MarkView> views = mark_views(sheep, arm);
  for (const auto& mv : views) blend_disc(mv.centre_px, mv.radius_px, config_.mark_level);
  // The arm is above everything on the table: drawn last, it hides what it covers.
  for (const auto& part : arm) blend_capsule(project(part), config_.arm_level);
  if (light != nullptr && light->radius_px > 0.0) {
    const auto& t = light->tip_mm;
    if (t.allFinite() && t.z() < cam.height_mm)
      blend_disc(cam.project(t.x(), t.y(), t.z()), light->radius_px, light->level);
  }
  for (const auto& cloud : clouds) blend_cloud(cloud);

  // One pass a compiler vectorises: no wrap of the noise index (the table
  // holds more than four frames, so a frame's samples are one run of it), and
  // rounding as floor(g + 0.5) after clamping, which equals lround for the
  // clamped range.
  const size_t n = scene_.size();
  image.resize(n);
  const float sigma = static_cast<float>(config_.noise_sigma);
  std::uniform_int_distribution<size_t> start(0, noise_table_.size() - n);
  const float* noise = noise_table_.data() + start(rng_);
  const float* gain = gain_.data();
  const float* scene = scene_.data();
  uint8_t* out = image.data();
  for (size_t i = 0; i < n; ++i) {
    const float g = gain[i] * scene[i] + sigma * noise[i] + 0.5f;
    out[i] = static_cast<uint8_t>(static_cast<int>(std::clamp(g, 0.0f, 255.0f)));
  }
  return views;
}

}  // namespace ephor::sim
