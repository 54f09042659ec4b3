// The whole calibration procedure against procs/shepherd/sim's Simulator in-process (no
// LCM): move the tool to each point of the plan with slow joint moves, find
// the light by on/off differencing, fit, and compare with the true camera.

#include <cmath>

#include <gtest/gtest.h>

#include "common/arm/arm_workcell.h"
#include "common/calibration/field_calibration.h"
#include "common/shepherd/calibrate/calibration_plan.h"
#include "common/shepherd/calibrate/joint_move.h"
#include "common/shepherd/calibrate/tool_spot_finder.h"
#include "common/shepherd/sim/simulator.h"

namespace ephor::calibrate {
namespace {

using calibration::Plane;

GreyFrame frame(sim::Simulator& s) {
  GreyFrame f{s.camera().width(), s.camera().height(), {}};
  s.render(f.data);
  return f;
}

// Worst error over a grid covering the field (mm) of the calibration against
// the true camera, in one plane.
double worst_error_mm(const calibration::FieldCalibration& cal, const geometry::OverheadCamera& cam,
                      const geometry::Workcell& cell, Plane plane) {
  const double z = plane == Plane::kObject ? cell.object_plane_z_mm : cell.elevation_plane_z_mm;
  double worst = 0.0;
  for (double x = 0.0; x <= cell.field_length_mm; x += cell.field_length_mm / 10)
    for (double y = 0.0; y <= cell.field_width_mm; y += cell.field_width_mm / 10) {
      const Eigen::Vector2d px = cam.project(x, y, z);
      worst = std::max(worst,
                       (cal.image_to_field(px.x(), px.y(), plane) - Eigen::Vector2d(x, y)).norm());
    }
  return worst;
}

TEST(CalibrateSim, CalibrationAgreesWithTheTrueCameraToAMillimetre) {
  sim::SimulatorConfig config;
  config.world.sheep = 3;  // sheep on the field: their marks must not disturb the light
  config.world.seed = 5;
  sim::Simulator s(config);
  const auto& cell = config.world.workcell;
  const CalibrationPlan plan(cell);
  const ToolSpotFinder finder;
  std::vector<calibration::Correspondence> object, elevation;
  int64_t seq = 1000000;
  for (const auto& stop : plan.stops()) {
    const auto goal = s.puma().nearest_inverse(
        arm::tool_down_pose(cell, stop.tip_mm.x(), stop.tip_mm.y(), stop.tip_mm.z(), 0.0),
        s.servo().q);
    ASSERT_TRUE(goal) << "IK failed at " << stop.tip_mm.transpose();
    const JointPath path = JointMove::plan(s.servo().q, *goal, s.puma().limits());
    sim::JointTrajectory t{++seq, path.t_s, path.q, path.qd};
    ASSERT_TRUE(s.follow(t));
    for (double waited = 0.0; !s.servo().trajectory_done && waited < path.duration_s() + 5.0;
         waited += 0.01)
      s.step(0.01);
    ASSERT_TRUE(s.servo().trajectory_done) << "move to " << stop.tip_mm.transpose();
    ASSERT_FALSE(s.servo().fault) << s.servo().fault_reason;
    s.step(0.2);  // settle
    if (!stop.measure) continue;
    s.set_tool_light(false);
    const GreyFrame dark = frame(s);
    s.step(1.0 / 30);
    s.set_tool_light(true);
    const GreyFrame lit = frame(s);
    s.set_tool_light(false);
    const auto spot = finder.find(lit, dark);
    ASSERT_TRUE(spot.spot) << "at " << stop.tip_mm.transpose() << ": " << spot.reason;
    // The tip as the joint encoders say, not as commanded.
    const Eigen::Vector3d tip = arm::tool_in_field(cell, s.servo().q).tip_mm;
    EXPECT_LT((tip - stop.tip_mm).norm(), 2.0);
    (stop.plane == Plane::kObject ? object : elevation)
        .push_back({spot.spot->centre_px, tip.head<2>()});
  }
  const auto cal = calibration::FieldCalibration::fit(object, elevation);
  const auto& cam = config.camera.camera;
  const double obj = worst_error_mm(cal, cam, cell, Plane::kObject);
  const double ele = worst_error_mm(cal, cam, cell, Plane::kElevation);
  std::printf("worst error over the field: object plane %.3f mm, elevation plane %.3f mm\n", obj,
              ele);
  EXPECT_LT(obj, 1.0);
  EXPECT_LT(ele, 1.0);
}

}  // namespace
}  // namespace ephor::calibrate
