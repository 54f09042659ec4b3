#include "common/stripe/cloud_file.h"

#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

namespace ephor::stripe {
namespace {

TEST(CloudFileTest, PlyRoundTripInMillimetres) {
  const std::string path =
      (std::filesystem::temp_directory_path() / "ephor_stripe_cloud_test.ply").string();
  std::vector<Eigen::Vector3d> pts{{-200.25, 13.5, 20.0}, {0.0, 0.0, 0.0}, {199.75, -7.125, 95.5}};
  save_cloud_ply(path, pts);
  const auto back = load_cloud_ply(path);
  ASSERT_EQ(back.size(), pts.size());
  for (size_t i = 0; i < pts.size(); ++i) EXPECT_LT((back[i] - pts[i]).norm(), 1e-4);
  std::filesystem::remove(path);
}

TEST(CloudFileTest, BadInputIsAClearError) {
  EXPECT_THROW(save_cloud_ply("/nonexistent-dir/x.ply", {{1, 2, 3}}), CloudFileError);
  EXPECT_THROW(save_cloud_ply("/tmp/ephor_nan.ply", {{1, NAN, 3}}), CloudFileError);
  EXPECT_THROW(load_cloud_ply("/nonexistent-dir/x.ply"), CloudFileError);
}

}  // namespace
}  // namespace ephor::stripe
