#include "common/rambo/image_triple.h"

#include <cmath>

namespace ephor::rambo {

bool CameraIntrinsics::valid() const {
  return std::isfinite(fx_px) && std::isfinite(fy_px) && fx_px > 0 && fy_px > 0 &&
         std::isfinite(cx_px) && std::isfinite(cy_px) && width_px > 0 && height_px > 0;
}

std::vector<ImageTriple> synthetic_image_triples(const TargetModel& model,
                                                 const CameraIntrinsics& camera,
                                                 const Eigen::Isometry3d& target_in_camera,
                                                 double noise_px, std::mt19937* rng) {
  const Eigen::Vector3d cam_in_target = target_in_camera.inverse().translation();
  const std::vector<bool> vis_v = model.visible_vertices(cam_in_target);
  const std::vector<bool> vis_e = model.visible_edges(cam_in_target);
  const std::size_t nv = model.vertices().size();
  std::vector<Eigen::Vector2d> px(nv);
  std::vector<bool> ok(nv, false);
  std::normal_distribution<double> n(0.0, 1.0);
  for (std::size_t v = 0; v < nv; ++v) {
    const Eigen::Vector3d p = target_in_camera * model.vertices()[v];
    if (!vis_v[v] || p.z() <= 1.0) continue;
    px[v] = camera.project(p);
    if (noise_px > 0.0 && rng) px[v] += noise_px * Eigen::Vector2d(n(*rng), n(*rng));
    ok[v] = px[v].x() >= 0 && px[v].y() >= 0 && px[v].x() <= camera.width_px - 1 &&
            px[v].y() <= camera.height_px - 1;
  }
  std::vector<std::vector<int>> joined(nv);
  for (std::size_t e = 0; e < model.edges().size(); ++e) {
    const auto& ed = model.edges()[e];
    if (!vis_e[e] || !ok[static_cast<std::size_t>(ed[0])] || !ok[static_cast<std::size_t>(ed[1])])
      continue;
    joined[static_cast<std::size_t>(ed[0])].push_back(ed[1]);
    joined[static_cast<std::size_t>(ed[1])].push_back(ed[0]);
  }
  std::vector<ImageTriple> out;
  for (std::size_t v = 0; v < nv; ++v) {
    const auto& j = joined[v];
    for (std::size_t a = 0; a < j.size(); ++a)
      for (std::size_t b = a + 1; b < j.size(); ++b)
        out.push_back(
            {px[v], px[static_cast<std::size_t>(j[a])], px[static_cast<std::size_t>(j[b])], {}});
  }
  return out;
}

}  // namespace ephor::rambo
