#include "common/rambo/target_renderer.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace ephor::rambo {

TargetRenderer::TargetRenderer(TargetModel model, CameraIntrinsics camera, double noise_grey,
                               std::uint64_t seed)
    : model_(std::move(model)), camera_(camera), noise_grey_(noise_grey), rng_(seed) {}

int TargetRenderer::render(const Eigen::Isometry3d& target_in_camera, cv::Mat& image,
                           const std::vector<RenderedLink>& links) {
  image.create(camera_.height_px, camera_.width_px, CV_8UC1);
  image.setTo(cv::Scalar(25));
  for (const RenderedLink& l : links) {
    if (!(l.a_mm.z() >= 10.0 && l.b_mm.z() >= 10.0) || !(l.radius_mm > 0.0)) continue;
    const Eigen::Vector2d a = camera_.project(l.a_mm), b = camera_.project(l.b_mm);
    // Width at the nearer end's depth; at most the image's width.
    const double width_px =
        std::min(2.0 * l.radius_mm * camera_.fx_px / std::min(l.a_mm.z(), l.b_mm.z()),
                 static_cast<double>(camera_.width_px));
    if (!a.allFinite() || !b.allFinite() || a.cwiseAbs().maxCoeff() > 1e5 ||
        b.cwiseAbs().maxCoeff() > 1e5)
      continue;
    // 1/16 px fixed point, as the faces.
    cv::line(image,
             cv::Point(static_cast<int>(std::lround(a.x() * 16.0)),
                       static_cast<int>(std::lround(a.y() * 16.0))),
             cv::Point(static_cast<int>(std::lround(b.x() * 16.0)),
                       static_cast<int>(std::lround(b.y() * 16.0))),
             cv::Scalar(95), std::max(1, static_cast<int>(std::lround(width_px))), cv::LINE_AA, 4);
  }
  const Eigen::Vector3d camera_in_target = target_in_camera.inverse().translation();
  int drawn = 0;
  for (int f = 0; f < static_cast<int>(model_.faces().size()); ++f) {
    const auto& face = model_.faces()[static_cast<std::size_t>(f)];
    const Eigen::Vector3d& n = model_.face_normal(f);
    const Eigen::Vector3d on_face = model_.vertices()[static_cast<std::size_t>(face.front())];
    if (n.dot(camera_in_target - on_face) <= 0.0) continue;  // back face (convex target)
    std::vector<cv::Point> poly;
    bool in_front = true;
    for (int v : face) {
      const Eigen::Vector3d p = target_in_camera * model_.vertices()[static_cast<std::size_t>(v)];
      if (p.z() < 10.0) in_front = false;
      const Eigen::Vector2d px = camera_.project(p);
      // 1/16 px fixed point for sub-pixel corners.
      poly.emplace_back(static_cast<int>(std::lround(px.x() * 16.0)),
                        static_cast<int>(std::lround(px.y() * 16.0)));
    }
    if (!in_front) continue;
    // Lambert shading, light from the camera: brightness by the face's tilt.
    const Eigen::Vector3d n_cam = target_in_camera.linear() * n;
    const Eigen::Vector3d to_cam = -(target_in_camera * on_face).normalized();
    const double shade = 60.0 + 180.0 * std::max(0.0, n_cam.dot(to_cam));
    const cv::Point* pts = poly.data();
    const int count = static_cast<int>(poly.size());
    cv::fillPoly(image, &pts, &count, 1, cv::Scalar(shade), cv::LINE_AA, 4);
    ++drawn;
  }
  cv::GaussianBlur(image, image, cv::Size(3, 3), 0.8);
  if (noise_grey_ > 0.0) {
    cv::Mat noise(image.size(), CV_16SC1);
    rng_.fill(noise, cv::RNG::NORMAL, 0.0, noise_grey_);
    cv::Mat wide;
    image.convertTo(wide, CV_16SC1);
    wide += noise;
    wide.convertTo(image, CV_8UC1);  // saturates to [0, 255]
  }
  return drawn;
}

}  // namespace ephor::rambo
