#include "procs/shepherd/display/overlay_geometry.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "common/geometry/overhead_camera.h"
#include "common/geometry/workcell.h"

namespace ephor::display {
namespace {

TEST(OverlayGeometryTest, CircleHasTheBlobsArea) {
  EXPECT_NEAR(std::numbers::pi * std::pow(OverlayGeometry::blob_radius_px(150.0), 2), 150.0, 1e-9);
  EXPECT_EQ(OverlayGeometry::blob_radius_px(0.0), 0.0);
  EXPECT_EQ(OverlayGeometry::blob_radius_px(std::nan("")), 0.0);
}

TEST(OverlayGeometryTest, PredictedPathFollowsTheVelocity) {
  const auto path = OverlayGeometry::predicted_path(100, 50, 10, -4, 3.0, 3);
  ASSERT_EQ(path.size(), 4u);
  EXPECT_DOUBLE_EQ(path.front().u, 100);
  EXPECT_DOUBLE_EQ(path.back().u, 130);
  EXPECT_DOUBLE_EQ(path.back().v, 38);
}

TEST(OverlayGeometryTest, FieldCornersProjectWhereTheSimCameraSeesThem) {
  const geometry::Workcell cell;
  const geometry::OverheadCamera camera;
  const auto cal = calibration::FieldCalibration::from_camera(camera, cell);
  const OverlayGeometry g(cal.matrix_at_height(0.0), cell.field_length_mm, cell.field_width_mm);
  const auto& b = g.field_boundary();
  ASSERT_EQ(b.size(), 4u);
  // The field origin is bottom-left in the image, x to the right, y up.
  EXPECT_LT(b[0].u, b[1].u);
  EXPECT_GT(b[0].v, b[3].v);
  // Every corner maps back to its field point.
  const double xs[4] = {0, cell.field_length_mm, cell.field_length_mm, 0};
  const double ys[4] = {0, 0, cell.field_width_mm, cell.field_width_mm};
  for (int i = 0; i < 4; ++i) {
    const auto f =
        cal.image_to_field_at_height(b[static_cast<size_t>(i)].u, b[static_cast<size_t>(i)].v, 0.0);
    EXPECT_NEAR(f.x(), xs[i], 1e-6);
    EXPECT_NEAR(f.y(), ys[i], 1e-6);
  }
  EXPECT_GT(g.px_per_mm(), 0.1);
  EXPECT_LT(g.px_per_mm(), 1.0);
}

TEST(OverlayGeometryTest, SingularMapIsRefused) {
  calibration::AffineMap m = calibration::AffineMap::Zero();
  EXPECT_THROW(OverlayGeometry(m, 100, 100), std::invalid_argument);
}

}  // namespace
}  // namespace ephor::display
