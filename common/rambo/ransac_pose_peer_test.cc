// The solvePnPRansac peer on hand-checked cases: noise-free projections of
// the cut box give its pose back; too few points give none.
#include "common/rambo/ransac_pose_peer.h"

#include <cmath>

#include <gtest/gtest.h>

namespace ephor::rambo {
namespace {

TEST(RansacPosePeer, RecoversANoiseFreePoseFromAllHypotheses) {
  const TargetModel box = TargetModel::truncated_box(140, 100, 70, Eigen::Vector3d(40, 30, 25));
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
  truth.linear() =
      (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) *
       Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d(1, 1, 1).normalized(),
                                          Eigen::Vector3d(0.2, -0.1, -1.0).normalized()))
          .toRotationMatrix();
  truth.translation() << 30.0, -20.0, 600.0;
  const CameraIntrinsics cam;
  const auto triples = synthetic_image_triples(box, cam, truth, 0.0, nullptr);
  ASSERT_GE(triples.size(), 10u);
  const RansacPosePeer peer(box, cam);
  const auto p = peer.estimate(triples);
  ASSERT_TRUE(p.has_value());
  EXPECT_LT((p->target_in_camera.translation() - truth.translation()).norm(), 0.5);
  EXPECT_LT(Eigen::AngleAxisd(p->target_in_camera.linear().transpose() * truth.linear()).angle(),
            0.2 * M_PI / 180.0);
  EXPECT_GE(p->inliers, 7);  // the 7 visible vertices (the cut corner's 3, 4 box corners)
  // Every distinct image point (a visible vertex) paired with each of the 10 vertices.
  EXPECT_EQ(p->hypotheses, 10 * p->inliers);
  // Fewer than 4 distinct points: no pose; NaN pixels are not points.
  std::vector<ImageTriple> one{triples.front()};
  one.front().a_px.x() = std::nan("");
  EXPECT_FALSE(peer.estimate(one).has_value());
  EXPECT_FALSE(peer.estimate({}).has_value());
}

}  // namespace
}  // namespace ephor::rambo
