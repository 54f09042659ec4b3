#include "common/geometry/overhead_camera.h"

#include <gtest/gtest.h>

#include "common/geometry/workcell.h"

namespace ephor::geometry {
namespace {

TEST(OverheadCamera, WholeFieldIsInTheImage) {
  const OverheadCamera cam;
  const Workcell cell;
  for (double x : {0.0, cell.field_length_mm})
    for (double y : {0.0, cell.field_width_mm})
      for (double z : {0.0, cell.elevation_plane_z_mm}) {
        const auto p = cam.project(x, y, z);
        EXPECT_GE(p.x(), 0.0);
        EXPECT_LE(p.x(), cam.width_px - 1.0);
        EXPECT_GE(p.y(), 0.0);
        EXPECT_LE(p.y(), cam.height_px - 1.0);
      }
}

TEST(OverheadCamera, FieldYUpIsImageVDown) {
  const OverheadCamera cam;
  EXPECT_GT(cam.project(600, 0, 0).y(), cam.project(600, 900, 0).y());
  EXPECT_LT(cam.project(0, 400, 0).x(), cam.project(1200, 400, 0).x());
}

TEST(OverheadCamera, UnprojectInvertsProjectOnEachPlane) {
  const OverheadCamera cam;
  for (double z : {0.0, 30.0, 200.0}) {
    const auto p = cam.project(123.0, 777.0, z);
    const auto q = cam.unproject(p.x(), p.y(), z);
    EXPECT_NEAR(q.x(), 123.0, 1e-9);
    EXPECT_NEAR(q.y(), 777.0, 1e-9);
  }
}

TEST(OverheadCamera, SheepMarkOfFortyTwoMillimetresIsAboutSixteenPixels) {
  const OverheadCamera cam;
  EXPECT_NEAR(42.0 * cam.px_per_mm(60.0), 16.0, 1.0);
}

}  // namespace
}  // namespace ephor::geometry
