// The peer: PCL's sphere RANSAC (SACMODEL_SPHERE, radius limits) and its
// refinement (optimizeModelCoefficients: Levenberg-Marquardt over the
// inliers) on the same foreground points as the paper's algorithms.
//
// PCL's sphere model is static, so the moving sphere is fitted as if it
// stood still: the centre is taken as the position at the points' mean time
// (the motion is symmetric about it to first order) and no velocity is
// estimated (reported as zero). The radius is free within [0.07, 0.09] m
// (PCL fits it; the paper's algorithms know it).
//
// PCL headers are heavy: they stay in this one file.

#include "procs/sphere/bench/pcl_sphere_peer.h"

#include <pcl/ModelCoefficients.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/segmentation/sac_segmentation.h>

#include "common/sphere/foreground_gate.h"

namespace ephor::sphere {

bool pcl_peer_available() { return true; }

Estimate pcl_sphere_locate(const Window& window) {
  ForegroundGate gate;
  if (gate.learn(window) == 0)
    return Estimate::none("no returns closer than the background threshold");
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  double t_sum = 0.0;
  int lines = 0;
  for (const ScanLine& line : window.lines) {
    bool any = false;
    for (const Pulse& p : line.pulses) {
      if (!gate.is_foreground(p)) continue;
      const Eigen::Vector3d q = to_cartesian(p.azimuth_rad, p.elevation_rad, p.range_m);
      cloud->push_back(pcl::PointXYZ(static_cast<float>(q.x()), static_cast<float>(q.y()),
                                     static_cast<float>(q.z())));
      t_sum += p.t_s;
      any = true;
    }
    lines += any ? 1 : 0;
  }
  const int n = static_cast<int>(cloud->size());
  if (n < 12)
    return Estimate::none("only " + std::to_string(n) + " points on the sphere", n, lines);
  // Float coordinates at 20 m keep ~2 um: far below the noise.
  pcl::SACSegmentation<pcl::PointXYZ> seg;
  seg.setOptimizeCoefficients(true);
  seg.setModelType(pcl::SACMODEL_SPHERE);
  seg.setMethodType(pcl::SAC_RANSAC);
  seg.setDistanceThreshold(0.04);  // 2 sigma of the range noise
  seg.setRadiusLimits(0.06, 0.10);
  seg.setMaxIterations(200);
  seg.setInputCloud(cloud);
  pcl::PointIndices inliers;
  pcl::ModelCoefficients coefficients;
  seg.segment(inliers, coefficients);
  if (inliers.indices.empty() || coefficients.values.size() != 4) {
    return Estimate::none("PCL found no sphere", n, lines);
  }
  Estimate e;
  e.ok = true;
  e.t_s = t_sum / n;
  e.position_m =
      Eigen::Vector3d(coefficients.values[0], coefficients.values[1], coefficients.values[2]);
  e.points = static_cast<int>(inliers.indices.size());
  e.lines = lines;
  return e;
}

}  // namespace ephor::sphere
