#include "common/stripe/cloud_file.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>

#include <pcl/PCLPointCloud2.h>
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
  // Read into PCL's untyped cloud and take x, y, z out ourselves, after
  // checking that its sizes agree: PCL's own conversion to PointXYZ
  // (fromPCLPointCloud2) trusts them, and a malformed header (an unknown
  // element before the properties) made it index past the points it had
  // allocated (found by fuzz_stripe_cloud_ply, UBSan; a heap overrun without).
  pcl::PCLPointCloud2 blob;
  if (pcl::io::loadPLYFile(path, blob) < 0)
    throw CloudFileError("cloud file " + path + ": cannot be read as PLY");
  const auto bad = [&path](const std::string& why) {
    return CloudFileError("cloud file " + path + ": " + why);
  };
  std::array<std::size_t, 3> offset{};
  std::array<bool, 3> single{};  // float, else double
  const char* const names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    const auto it = std::find_if(blob.fields.begin(), blob.fields.end(),
                                 [&](const pcl::PCLPointField& f) { return f.name == names[k]; });
    if (it == blob.fields.end()) throw bad(std::string("no vertex property ") + names[k]);
    if (it->datatype != pcl::PCLPointField::FLOAT32 && it->datatype != pcl::PCLPointField::FLOAT64)
      throw bad(std::string("vertex property ") + names[k] + " is not float or double");
    const std::size_t size = it->datatype == pcl::PCLPointField::FLOAT32 ? 4 : 8;
    if (std::size_t{it->offset} + size > blob.point_step)
      throw bad("the vertex properties do not fit the vertex size");
    offset[static_cast<std::size_t>(k)] = it->offset;
    single[static_cast<std::size_t>(k)] = size == 4;
  }
  const std::uint64_t width = blob.width, height = blob.height;
  if (width == 0 || height == 0) return {};
  if (std::uint64_t{blob.row_step} < width * blob.point_step ||
      std::uint64_t{blob.data.size()} < height * blob.row_step)
    throw bad("its vertex count disagrees with its data");
  std::vector<Eigen::Vector3d> out;
  out.reserve(static_cast<std::size_t>(width * height));
  for (std::uint64_t row = 0; row < height; ++row) {
    for (std::uint64_t col = 0; col < width; ++col) {
      const std::uint8_t* point = blob.data.data() + row * blob.row_step + col * blob.point_step;
      Eigen::Vector3d p;
      for (std::size_t k = 0; k < 3; ++k) {
        if (single[k]) {
          float v = 0.0f;
          std::memcpy(&v, point + offset[k], sizeof v);
          p[static_cast<Eigen::Index>(k)] = static_cast<double>(v);
        } else {
          double v = 0.0;
          std::memcpy(&v, point + offset[k], sizeof v);
          p[static_cast<Eigen::Index>(k)] = static_cast<double>(v);
        }
      }
      out.push_back(p);
    }
  }
  return out;
}

}  // namespace ephor::stripe
