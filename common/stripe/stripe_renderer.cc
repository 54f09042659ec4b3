#include "common/stripe/stripe_renderer.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

namespace ephor::stripe {

namespace {
constexpr double kFwhmToSigma = 1.0 / 2.354820045;  // 2 sqrt(2 ln 2)
}

StripeRenderer::StripeRenderer(const StripeScene& scene, CameraIntrinsics camera,
                               StripeRendererOptions options)
    : scene_(&scene), camera_(camera), options_(options) {
  if (!camera_.valid()) throw std::invalid_argument("StripeRenderer: invalid camera intrinsics");
  if (!(options_.laser.width_fwhm_mm > 0.0) || !(options_.laser.reference_range_mm > 0.0) ||
      !(options_.laser.fan_half_angle_rad > 0.0))
    throw std::invalid_argument("StripeRenderer: laser sheet sizes must be > 0");
  if (options_.dot_radii_mm.size() != options_.dots_mm.size())
    throw std::invalid_argument("StripeRenderer: one radius per target dot");
}

double StripeRenderer::sheet_sigma_mm(double range_mm) const {
  return options_.laser.width_fwhm_mm * kFwhmToSigma * range_mm / options_.laser.reference_range_mm;
}

double StripeRenderer::irradiance(const Eigen::Isometry3d& s, const Eigen::Vector3d& p,
                                  const Eigen::Vector3d& normal) const {
  const Eigen::Vector3d ps = s.inverse() * p;
  if (ps.z() <= 0.0 || std::abs(ps.y()) > ps.z() * std::tan(options_.laser.fan_half_angle_rad))
    return 0.0;
  const Eigen::Vector3d to_proj = s.translation() - p;
  const double r = to_proj.norm();
  const double cos_i = normal.dot(to_proj) / r;
  if (cos_i <= 0.0) return 0.0;
  // Shadow: anything between the projector and p (a 0.05 mm margin keeps p's
  // own face out).
  if (scene_->occluded(s.translation(), -to_proj / r, 1e-6, r - 0.05)) return 0.0;
  const double rr = options_.laser.reference_range_mm / r;
  return cos_i * rr * rr;
}

cv::Mat StripeRenderer::render(const Eigen::Isometry3d& c, const Eigen::Isometry3d& s,
                               std::uint64_t seed) const {
  const int w = camera_.width_px, h = camera_.height_px;
  cv::Mat_<float> img(h, w);
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> noise(0.0f, static_cast<float>(options_.noise_sigma_grey));
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
      img(v, u) = static_cast<float>(options_.background_grey) +
                  (options_.noise_sigma_grey > 0.0 ? noise(rng) : 0.0f);

  const Eigen::Vector3d o = c.translation();
  const Eigen::Vector3d n = s.linear().col(0);  // light plane normal (x of S)
  const Eigen::Vector3d s0 = s.translation();
  const double f0 = n.dot(o - s0);  // camera centre's distance from the plane
  // Pixels whose first surface is within `band` of the plane can be lit:
  // 4 sigma of a sheet at up to 2x the reference range, plus a pixel's
  // footprint on steep faces.
  const double band = 8.0 * sheet_sigma_mm(options_.laser.reference_range_mm) + 2.0;
  const double far = 1e5;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const Eigen::Vector3d d = c.linear() * camera_.ray(u, v);
      const double f1 = n.dot(d);
      double t_lo = 0.0, t_hi = far;
      if (std::abs(f1) > 1e-12) {
        t_lo = (-band - f0) / f1;
        t_hi = (band - f0) / f1;
        if (t_lo > t_hi) std::swap(t_lo, t_hi);
        if (t_hi <= 0.0) continue;
        t_lo = std::max(t_lo, 0.0);
      } else if (std::abs(f0) > band) {
        continue;
      }
      // Cheap first: is there any surface in the band at all?
      if (!scene_->occluded(o, d, t_lo, t_hi)) continue;
      const auto hit = scene_->first_hit(o, d, 1e-6, t_hi);
      if (!hit || hit->t < t_lo) continue;  // something nearer hides the band
      const double e = irradiance(s, hit->point, hit->normal);
      if (e <= 0.0) continue;
      // Distance from the sheet at the pixel's centre and its change across
      // the pixel (the neighbouring ray at u + 0.5 on the same face's plane).
      const double d0 = n.dot(hit->point - s0);
      const Eigen::Vector3d d_half = c.linear() * camera_.ray(u + 0.5, v);
      const double den = hit->normal.dot(d_half);
      double slope = 0.0;  // mm of sheet distance per pixel
      if (std::abs(den) > 1e-9) {
        const double t2 = hit->normal.dot(hit->point - o) / den;
        slope = 2.0 * (n.dot(o + t2 * d_half - s0) - d0);
      }
      const double sigma = sheet_sigma_mm((hit->point - s0).norm());
      double profile = 0.0;
      const double k = 1.0 / (sigma * std::numbers::sqrt2);
      if (std::abs(slope) < 1e-6 * sigma) {
        profile = std::exp(-0.5 * d0 * d0 / (sigma * sigma));
      } else {
        const double a = std::abs(slope);
        profile = sigma * std::sqrt(std::numbers::pi / 2.0) / a *
                  (std::erf((d0 + 0.5 * a) * k) - std::erf((d0 - 0.5 * a) * k));
      }
      img(v, u) += static_cast<float>(options_.peak_grey * e * profile);
    }
  }
  cv::Mat out;
  img.convertTo(out, CV_8UC1);  // rounds and saturates
  return out;
}

cv::Mat StripeRenderer::render_ambient(const Eigen::Isometry3d& c, std::uint64_t seed) const {
  const int w = camera_.width_px, h = camera_.height_px;
  cv::Mat_<float> img(h, w);
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> noise(0.0f, static_cast<float>(options_.noise_sigma_grey));
  // 3 x 3 samples a pixel so the spot's edge is anti-aliased (sub-pixel centroids).
  constexpr int kSub = 3;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      double sum = 0.0;
      for (int sv = 0; sv < kSub; ++sv) {
        for (int su = 0; su < kSub; ++su) {
          const double uu = u + (su + 0.5) / kSub - 0.5, vv = v + (sv + 0.5) / kSub - 0.5;
          const Eigen::Vector3d d = c.linear() * camera_.ray(uu, vv);
          const auto hit = scene_->first_hit(c.translation(), d, 1e-6, 1e5);
          if (!hit) continue;
          if (hit->face >= 0) {
            sum += options_.object_grey * std::abs(hit->normal.z());
          } else {
            const Eigen::Vector2d at = hit->point.head<2>();
            bool dark = (at - options_.spot_centre_mm).norm() <= options_.spot_radius_mm;
            for (size_t k = 0; !dark && k < options_.dots_mm.size(); ++k)
              dark = (at - options_.dots_mm[k]).norm() <= options_.dot_radii_mm[k];
            sum += dark ? options_.spot_grey : options_.table_grey;
          }
        }
      }
      img(v, u) = static_cast<float>(sum / (kSub * kSub)) +
                  (options_.noise_sigma_grey > 0.0 ? noise(rng) : 0.0f);
    }
  }
  cv::Mat out;
  img.convertTo(out, CV_8UC1);
  return out;
}

}  // namespace ephor::stripe
