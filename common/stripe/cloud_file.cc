#include "common/stripe/cloud_file.h"

#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace ephor::stripe {

void save_cloud_ply(const std::string& path, const std::vector<Eigen::Vector3d>& points_mm) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.reserve(points_mm.size());
  for (size_t i = 0; i < points_mm.size(); ++i) {
    const Eigen::Vector3d& p = points_mm[i];
    if (!p.allFinite())
      throw CloudFileError("cloud file " + path + ": point " + std::to_string(i) +
                           " is not finite");
    cloud.push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                  static_cast<float>(p.z())));
  }
  if (cloud.empty()) {
    // PCL refuses to write an empty cloud; an empty scan is still a scan.
    cloud.width = 0;
    cloud.height = 1;
  }
  // No camera element: PCL's own reader and other tools warn about it.
  pcl::PLYWriter writer;
  if (writer.write(path, cloud, /*binary=*/true, /*use_camera=*/false) < 0)
    throw CloudFileError("cloud file " + path + ": cannot be written");
}

std::vector<Eigen::Vector3d> load_cloud_ply(const std::string& path) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  if (pcl::io::loadPLYFile(path, cloud) < 0)
    throw CloudFileError("cloud file " + path + ": cannot be read as PLY");
  std::vector<Eigen::Vector3d> out;
  out.reserve(cloud.size());
  for (const auto& p : cloud.points) out.emplace_back(p.x, p.y, p.z);
  return out;
}

}  // namespace ephor::stripe
