#include "common/shepherd/calibrate/calibration_plan.h"

#include <gtest/gtest.h>

#include "common/arm/arm_workcell.h"

namespace ephor::calibrate {
namespace {

using calibration::Plane;

TEST(CalibrationPlan, SpreadsReachablePointsOverBothPlanes) {
  const geometry::Workcell cell;
  const CalibrationPlan plan(cell);
  EXPECT_EQ(plan.measured(Plane::kObject), 6);
  EXPECT_EQ(plan.measured(Plane::kElevation), 4);
  double min_x = 1e9, max_x = -1e9, min_y = 1e9, max_y = -1e9;
  for (const auto& s : plan.stops()) {
    EXPECT_TRUE(arm::reachable_tool_down(cell, s.tip_mm.x(), s.tip_mm.y(), s.tip_mm.z()));
    EXPECT_EQ(s.tip_mm.z(),
              s.plane == Plane::kObject ? cell.object_plane_z_mm : cell.elevation_plane_z_mm);
    if (s.plane != Plane::kObject) continue;
    min_x = std::min(min_x, s.tip_mm.x());
    max_x = std::max(max_x, s.tip_mm.x());
    min_y = std::min(min_y, s.tip_mm.y());
    max_y = std::max(max_y, s.tip_mm.y());
  }
  // Object-plane points span most of the field.
  EXPECT_GT(max_x - min_x, 0.8 * cell.field_length_mm);
  EXPECT_GT(max_y - min_y, 0.7 * cell.field_width_mm);
  // Every object-plane point is entered from above.
  const auto& st = plan.stops();
  for (size_t i = 1; i < st.size(); ++i)
    if (st[i].plane == Plane::kObject) {
      EXPECT_EQ(st[i - 1].plane, Plane::kElevation);
      EXPECT_NEAR((st[i - 1].tip_mm - st[i].tip_mm).head<2>().norm(), 0.0, 1e-9);
    }
}

TEST(CalibrationPlan, NamesAnUnreachablePoint) {
  const geometry::Workcell cell;
  try {
    CalibrationPlan(cell, {{{cell.centre_x_mm(), cell.centre_y_mm(), 30.0}, Plane::kObject, true}});
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("(609.5, 457.0, 30.0) mm in the object plane"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(CalibrationPlan(cell, {{{300.0, 300.0, 30.0}, Plane::kObject, true}}),
               std::invalid_argument);  // too few points
}

}  // namespace
}  // namespace ephor::calibrate
