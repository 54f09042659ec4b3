// The pieces together: arm, work cell, world, range finder, raster, plane fit.
#include <numbers>

#include <gtest/gtest.h>

#include "common/stripe/plane_fit.h"
#include "common/stripe/pyramid_apex.h"
#include "common/stripe/stripe_scan.h"

namespace ephor::stripe {
namespace {

TEST(TrueArmTest, NominalMatchesThePuma560AndErrorsMoveTheFlange) {
  const arm::Puma560 puma(0.0);
  const arm::Joints q = (arm::Joints() << 0.1, 0.4, -0.5, 0.2, 1.2, -0.3).finished();
  EXPECT_TRUE(TrueArm::nominal().flange(q).isApprox(puma.flange(q), 1e-12));
  // A zero-reference error is the same as turning the joint.
  arm::Joints off = arm::Joints::Zero();
  off[2] = 0.01;
  arm::Joints q2 = q;
  q2[2] += 0.01;
  EXPECT_TRUE(TrueArm::with_zero_offsets(off).flange(q).isApprox(puma.flange(q2), 1e-12));
  const ArmErrors e = ArmErrors::draw(3);
  EXPECT_EQ(e.zero_offset_rad[0], 0.0);
  for (int j = 1; j < 6; ++j) EXPECT_LE(std::abs(e.zero_offset_rad[j]), std::numbers::pi / 180);
  const double moved = (TrueArm(e).flange(q).translation() - puma.flange(q).translation()).norm();
  EXPECT_GT(moved, 0.5);
  EXPECT_LT(moved, 30.0);
}

TEST(PlaneFitTest, RecoversAPlaneAndItsThickness) {
  // Points on z = 0.1 x + 5 with +-0.2 mm alternating offsets along the normal.
  std::vector<Eigen::Vector3d> pts;
  const Eigen::Vector3d n = Eigen::Vector3d(-0.1, 0, 1).normalized();
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      pts.push_back(Eigen::Vector3d(i * 10.0, j * 10.0, 0.1 * i * 10.0 + 5.0) +
                    ((i + j) % 2 ? 0.2 : -0.2) * n);
  const auto f = PlaneFit::fit(pts);
  ASSERT_TRUE(f.has_value());
  EXPECT_NEAR(f->normal.dot(n), 1.0, 1e-12);
  EXPECT_NEAR(f->rms_mm, 0.2, 1e-9);
  EXPECT_NEAR(f->max_abs_mm, 0.2, 1e-9);
  EXPECT_FALSE(PlaneFit::fit({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}).has_value());
  EXPECT_FALSE(PlaneFit::fit({{0, 0, 0}, {1, 0, 0}}).has_value());
}

TEST(ScanGeometryTest, RasterCoversTheRegionAndTheSquareIsReachable) {
  RasterSpec spec;
  spec.x0_mm = -200;
  spec.x1_mm = 200;
  spec.y0_mm = -200;
  spec.y1_mm = 200;
  spec.step_mm = 10;
  const auto poses = raster_projector_poses(spec);
  // 4 passes of 120 mm cover 400 mm; 41 stripes each.
  EXPECT_EQ(poses.size(), 4u * 41u);
  const StripeWorkcell cell;
  const SensorCalibration cage = SensorCalibration::drawing_cage();
  arm::Joints q = StripeWorkcell::reference_joints();
  int unreachable = 0;
  for (const auto& s : poses) {
    const auto next = cell.joints_for(flange_for_projector(s, cage), q);
    if (!next) {
      ++unreachable;
      continue;
    }
    // The nominal model puts the projector where it was asked.
    const Eigen::Isometry3d back =
        cell.base_in_table * TrueArm::nominal().flange(*next) * cage.projector_in_flange;
    EXPECT_LT((back.translation() - s.translation()).norm(), 1e-6);
    q = *next;
  }
  EXPECT_EQ(unreachable, 0);
  EXPECT_THROW(raster_projector_poses(RasterSpec{0, 0, 10, 10, 0.0}), std::invalid_argument);
}

// Step 4 of the brief: the flat plate scanned with parallel stripes by the
// ideal robot; the band's thickness (1 sigma point-to-plane) against the
// paper's +-1 mm and the 0.3 mm target, and the plate's height.
TEST(ScanTest, FlatPlateRandomErrorWithinTarget) {
  const StripeScene scene = StripeScene::load(std::string(EPHOR_STRIPE_SCENES) + "/flat_plate.obj");
  const StripeWorld world(scene, StripeWorkcell{}, RobotTruth::ideal());
  const RangeFinder finder(StripeWorkcell{}, TrueArm::nominal(), SensorCalibration::drawing_cage());
  RasterSpec spec;
  spec.x0_mm = -40;
  spec.x1_mm = 40;
  spec.y0_mm = -50;
  spec.y1_mm = 50;
  spec.height_mm = 320;  // 300 mm above the plate's top
  const ScanResult r = run_scan(world, finder, raster_projector_poses(spec), 11);
  EXPECT_EQ(r.unreachable, 0);
  EXPECT_EQ(r.stripes.size(), 9u);
  const auto cloud = r.cloud();
  EXPECT_GT(cloud.size(), 9u * 250u);
  const auto fit = PlaneFit::fit(cloud);
  ASSERT_TRUE(fit.has_value());
  EXPECT_LT(fit->rms_mm, 0.3);
  EXPECT_NEAR(fit->centroid.z(), 20.0, 0.1);
  EXPECT_GT(fit->normal.z(), std::cos(0.001));
}

// The pyramid scene's apex (0, 0, 60) from a sweep straight down with the
// ideal robot, and from exact surface samples shifted by a known offset.
TEST(PyramidApexTest, LocatesTheApex) {
  std::vector<Eigen::Vector3d> pts;
  const Eigen::Vector3d shift(3.0, -2.0, 1.5);
  for (double x = -70; x <= 70; x += 2.5)
    for (double y = -70; y <= 70; y += 2.5) {
      const double z = std::max(0.0, 60.0 - std::max(std::abs(x), std::abs(y)));
      pts.push_back(Eigen::Vector3d(x, y, z) + shift);
    }
  const auto a = PyramidApex::locate(pts, Eigen::Vector3d(0, 0, 60));
  ASSERT_TRUE(a.has_value());
  EXPECT_LT((a->apex_mm - (Eigen::Vector3d(0, 0, 60) + shift)).norm(), 1e-6);

  const StripeScene scene = StripeScene::load(std::string(EPHOR_STRIPE_SCENES) + "/pyramid.obj");
  const StripeWorld world(scene, StripeWorkcell{}, RobotTruth::ideal());
  const RangeFinder finder(StripeWorkcell{}, TrueArm::nominal(), SensorCalibration::drawing_cage());
  const auto poses = sweep_projector_poses({0, 0, 60}, {0, 0, 1}, 280.0, {0, 1, 0}, 50.0, 10.0);
  ASSERT_EQ(poses.size(), 11u);
  const ScanResult r = run_scan(world, finder, poses, 3);
  EXPECT_EQ(r.unreachable, 0);
  const auto scanned = PyramidApex::locate(r.cloud(), Eigen::Vector3d(0, 0, 60));
  ASSERT_TRUE(scanned.has_value());
  EXPECT_LT((scanned->apex_mm - Eigen::Vector3d(0, 0, 60)).norm(), 0.2);
}

// Stray points (5 mm off a face) and a face seen only as a narrow band
// whose points are tilted (as a grazing view's few stripe points can be):
// the outliers are trimmed and the band is left out, so the apex stays
// where the three good faces put it; with the band kept it would not.
TEST(PyramidApexTest, TrimsStrayPointsAndDropsABandLikeFace) {
  std::vector<Eigen::Vector3d> pts;
  for (double x = -55; x <= 55; x += 2.5)
    for (double y = -55; y <= 55; y += 2.5) {
      const double z = 60.0 - std::max(std::abs(x), std::abs(y));
      const bool plus_x = x > std::abs(y);
      if (plus_x && !(y >= 10.0 && y <= 12.5)) continue;  // +x face: one band only
      // The band's heights tilted by 1 mm per 10 mm along x.
      pts.emplace_back(x, y, plus_x ? z + 0.1 * (x - 30.0) : z);
    }
  for (int i = 0; i < 10; ++i) pts.emplace_back(-30.0 + i, -5.0, 30.0 + i + 5.0);  // off -x face
  const auto a = PyramidApex::locate(pts, Eigen::Vector3d(0, 0, 60));
  ASSERT_TRUE(a.has_value());
  EXPECT_LT((a->apex_mm - Eigen::Vector3d(0, 0, 60)).norm(), 1e-6);
  PyramidApexOptions keep_all;
  keep_all.min_face_spread_mm = 0.0;
  keep_all.trim_rounds = 0;
  const auto b = PyramidApex::locate(pts, Eigen::Vector3d(0, 0, 60), keep_all);
  ASSERT_TRUE(b.has_value());
  EXPECT_GT((b->apex_mm - Eigen::Vector3d(0, 0, 60)).norm(), 0.5);
}

}  // namespace
}  // namespace ephor::stripe
