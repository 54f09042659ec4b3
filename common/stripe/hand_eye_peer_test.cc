#include "common/stripe/hand_eye_peer.h"

#include <map>
#include <numbers>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "common/stripe/dot_target.h"
#include "common/stripe/zero_reference_calibrator.h"

namespace ephor::stripe {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

double angle_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() / kDeg;
}

// A perfect arm (the nominal model is the truth), the cage 3.2 mm / 1.6 deg
// off its drawing (seed 4), no image noise: the spot and the dot target
// seen from the zero-reference step's views (every arm branch, one round)
// in the same images. OpenCV's hand-eye methods (target poses by PnP from
// the rendered dots, flange poses by the arm model) on the views within
// 120 deg of each other, and our zero-reference fit (the spot alone, all
// views), both find the camera's true pose on the flange.
TEST(HandEyePeerTest, OpenCvAndOursRecoverTheCameraOnAPerfectArm) {
  RobotTruth truth = RobotTruth::ideal();
  truth.cage = RobotTruth::draw(4).cage;
  const DotTarget target;
  StripeRendererOptions o;
  o.noise_sigma_grey = 0.0;
  o.dots_mm = target.dots_in_table();
  o.dot_radii_mm = target.dot_radii_mm();
  const StripeScene table;
  const StripeWorkcell cell;
  const StripeWorld world(table, cell, truth, o);

  ZeroReferenceOptions zo;
  zo.rounds = 1;
  const ZeroReferenceCalibrator zc(cell, zo);
  const TrueArm model = TrueArm::nominal();
  const SensorCalibration drawing = SensorCalibration::drawing_cage();
  const Eigen::Isometry3d& want = truth.cage.camera_in_flange;
  // The drawing is off by what must be found.
  ASSERT_GT((drawing.camera_in_flange.translation() - want.translation()).norm(), 3.0);
  ASSERT_GT(angle_deg(drawing.camera_in_flange, want), 1.5);

  std::vector<SpotSighting> spots;
  std::vector<HandEyeView> views;
  std::uint64_t seed = 1;
  for (const arm::Joints& q : zc.plan(model, drawing, Eigen::Vector2d::Zero())) {
    const cv::Mat image = world.spot_image(q, seed++);
    if (const auto s = find_spot(image)) spots.push_back({q, *s, std::cos(q[1]) > 0.0});
    if (const auto t = target.find(image, drawing.camera)) {
      EXPECT_LT(t->rms_px, 0.05);
      views.push_back({model.flange(q), t->target_in_camera});
    }
  }
  ASSERT_GE(views.size(), 40u);  // 46 seen
  const std::vector<HandEyeView> kept = views_within(views, 120.0);
  ASSERT_GE(kept.size(), 20u);  // 24 seen
  // Seen: 0.13-0.19 mm and 0.033 deg; LI's translation 0.79 mm (its
  // Kronecker product solves rotation and translation together).
  const std::map<HandEyeMethod, double> mm = {{HandEyeMethod::kLi, 1.5}};
  for (HandEyeMethod m : kHandEyeMethods) {
    const Eigen::Isometry3d got = solve_hand_eye(kept, m);
    const double tol_mm = mm.count(m) ? mm.at(m) : 0.4;
    EXPECT_LT((got.translation() - want.translation()).norm(), tol_mm) << hand_eye_method_name(m);
    EXPECT_LT(angle_deg(got, want), 0.06) << hand_eye_method_name(m);
  }
  // Ours, from the spot's pixels directly (no PnP in between): 0.011 mm,
  // 0.006 deg seen.
  const ZeroReferenceResult ours = zc.fit(spots, model, drawing);
  const Eigen::Isometry3d& got = ours.updated.camera_in_flange;
  EXPECT_LT((got.translation() - want.translation()).norm(), 0.05);
  EXPECT_LT(angle_deg(got, want), 0.015);
}

// Views turned near a half turn from each other are what OpenCV's TSAI
// and DANIILIDIS cannot take; views_within keeps a set within the limit.
TEST(HandEyePeerTest, ViewsWithinKeepsTheLargestSetWithinTheTurn) {
  auto view = [](double yaw_deg) {
    return HandEyeView{
        Eigen::Isometry3d(Eigen::AngleAxisd(yaw_deg * kDeg, Eigen::Vector3d::UnitZ())),
        Eigen::Isometry3d::Identity()};
  };
  const std::vector<HandEyeView> views = {view(0),  view(170), view(10),
                                          view(60), view(100), view(-30)};
  const std::vector<HandEyeView> kept = views_within(views, 120.0);
  ASSERT_EQ(kept.size(), 4u);  // -30, 0, 10, 60 (or 0, 10, 60, 100)
  for (const HandEyeView& a : kept)
    for (const HandEyeView& b : kept)
      EXPECT_LT(angle_deg(a.flange_in_base, b.flange_in_base), 120.0);
}

TEST(HandEyePeerTest, TooFewViewsIsAClearError) {
  const std::vector<HandEyeView> two(
      2, HandEyeView{Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity()});
  try {
    solve_hand_eye(two, HandEyeMethod::kTsai);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("2 views"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ephor::stripe
