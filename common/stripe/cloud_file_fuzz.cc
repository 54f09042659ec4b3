// Fuzz target (issue 18): a PLY point cloud as ephor reads one
// (load_cloud_ply: PCL's PLY reader, by path, as the stripe tests and a lab
// user's tools read a scan's --out file): any header (formats, element and
// property lists, counts), any body. Bad input must end in CloudFileError;
// a cloud that loads is written again with save_cloud_ply (its finite
// points) and must load back with as many points.
// Seeds: fuzz_corpus/stripe_cloud_ply (a few points as save_cloud_ply
// writes them, binary; the same in ASCII; a PLY with normals and colour).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/fuzz/fuzz_input.h"
#include "common/stripe/cloud_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static ephor::fuzz::FuzzInputFile file;
  static ephor::fuzz::FuzzInputFile again;
  std::vector<Eigen::Vector3d> cloud;
  try {
    cloud = ephor::stripe::load_cloud_ply(file.write(data, size));
  } catch (const ephor::stripe::CloudFileError& e) {
    if (std::string(e.what()).empty()) ephor::fuzz::fail("a refused cloud without a reason");
    return 0;
  }
  if (cloud.size() > 100'000) return 0;  // what the bytes allow is small; no huge rewrite
  std::vector<Eigen::Vector3d> finite;
  for (const auto& p : cloud)
    if (p.allFinite()) finite.push_back(p);
  try {
    again.write(nullptr, 0);
    ephor::stripe::save_cloud_ply(again.path(), finite);
    const auto back = ephor::stripe::load_cloud_ply(again.path());
    if (back.size() != finite.size())
      ephor::fuzz::fail("a written cloud loads back with another size");
  } catch (const ephor::stripe::CloudFileError& e) {
    ephor::fuzz::fail(std::string("a loaded cloud cannot be written and read again: ") + e.what());
  }
  return 0;
}
