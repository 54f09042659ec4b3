#pragma once
// Point clouds as PLY files (PCL's I/O: binary little-endian, float x y z, mm
// in the table frame), so PCL, Open3D and CloudCompare open them. The only
// file of ephor_stripe that includes PCL (library ephor_stripe_cloud).

#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace ephor::stripe {

class CloudFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws CloudFileError ("cloud file PATH: PROBLEM") when it cannot write or
// a point is not finite.
void save_cloud_ply(const std::string& path, const std::vector<Eigen::Vector3d>& points_mm);
// Throws CloudFileError when the file cannot be read or parsed.
std::vector<Eigen::Vector3d> load_cloud_ply(const std::string& path);

}  // namespace ephor::stripe
