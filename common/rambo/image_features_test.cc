#include "common/rambo/image_features.h"

#include <random>

#include <gtest/gtest.h>

#include "common/rambo/rambo_cell.h"
#include "common/rambo/target_renderer.h"
#include "common/rambo/triangle_pose_estimator.h"

namespace ephor::rambo {
namespace {

TEST(SymmetricNearestNeighbour, KeepsAStepAndRemovesAnOutlier) {
  cv::Mat g(9, 9, CV_8UC1, cv::Scalar(50));
  g(cv::Rect(5, 0, 4, 9)).setTo(200);  // a vertical step at x = 5
  g.at<uint8_t>(4, 2) = 120;           // an outlier on the dark side
  const cv::Mat f = symmetric_nearest_neighbour(g);
  EXPECT_EQ(f.at<uint8_t>(4, 4), 50);  // step edge kept sharp
  EXPECT_EQ(f.at<uint8_t>(4, 5), 200);
  EXPECT_LT(f.at<uint8_t>(4, 2), 120);  // outlier pulled towards its neighbours
  EXPECT_THROW(symmetric_nearest_neighbour(cv::Mat()), std::invalid_argument);
}

// A rendered view: corners near the projected visible vertices, triples, and
// the pose from them within a few mm of the truth.
TEST(ImageFeatures, RenderedTargetGivesCornersTriplesAndThePose) {
  const RamboCell cell = RamboCell::make(4);
  TargetRenderer renderer(cell.model, cell.camera, 3.0, 5);
  Eigen::Isometry3d in_camera = Eigen::Isometry3d::Identity();
  in_camera.linear() = (Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()) *
                        Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitX()))
                           .toRotationMatrix();
  in_camera.translation() = Eigen::Vector3d(10, -5, 420);
  cv::Mat image;
  renderer.render(in_camera, image);
  const ImageFeatures f = extract_image_features(image);
  std::mt19937 rng(1);
  const auto truth = synthetic_image_triples(cell.model, cell.camera, in_camera, 0.0, &rng);
  ASSERT_FALSE(truth.empty());
  // Every corner found lies on a projected vertex (within 2 px).
  std::vector<Eigen::Vector2d> vertices;
  for (const auto& v : cell.model.vertices())
    vertices.push_back(cell.camera.project(in_camera * v));
  int on_vertex = 0;
  for (const auto& c : f.corners_px) {
    double best = 1e9;
    for (const auto& v : vertices) best = std::min(best, (c - v).norm());
    on_vertex += best < 2.0 ? 1 : 0;
  }
  std::fprintf(stderr, "%zu corners (%d on vertices), %zu edges, %zu triples (truth %zu)\n",
               f.corners_px.size(), on_vertex, f.edges.size(), f.triples.size(), truth.size());
  EXPECT_GE(on_vertex, 5);
  EXPECT_GE(f.triples.size(), 4u) << f.reason;
  // The corners found fit one face: the pose with the prior's support (the
  // last pose, 5 mm and 2 deg off), "ambiguous view" without.
  const TrianglePoseEstimator estimator(cell.model, cell.camera, {});
  Eigen::Isometry3d prior = in_camera;
  prior.translation() += Eigen::Vector3d(3, -4, 0);
  prior.linear() = prior.linear() * Eigen::AngleAxisd(0.035, Eigen::Vector3d::UnitY());
  const TrianglePoseResult r = estimator.estimate(f.triples, &prior);
  ASSERT_TRUE(r.found) << r.reason;
  EXPECT_LT((r.target_in_camera.translation() - in_camera.translation()).norm(), 10.0);
  const TrianglePoseResult alone = estimator.estimate(f.triples);
  EXPECT_TRUE(alone.found || alone.reason.find("ambiguous view") != std::string::npos)
      << alone.reason;
  // A blank frame: no triples, with the reason.
  const ImageFeatures none = extract_image_features(cv::Mat(480, 640, CV_8UC1, cv::Scalar(25)));
  EXPECT_TRUE(none.triples.empty());
  EXPECT_FALSE(none.reason.empty());
}

}  // namespace
}  // namespace ephor::rambo
