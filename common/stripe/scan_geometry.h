#pragma once
// Where the sensor goes (paper 004, sections 1 and 5): the arm's place in the
// table frame, the flange pose that puts the projector at a chosen pose,
// the joint readings for it, and the paper's regular raster of stripes ("by
// stepping the range finder in 10 mm steps over the region of interest").
//
// Table frame: mm, z up, table top z = 0, the default cell scans the square
// x, y in [-200, 200] (issue 16). The PUMA's base frame (shoulder height) is
// `base_in_table`.

#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "common/arm/puma560.h"
#include "common/geometry/workcell.h"
#include "common/stripe/sensor_model.h"

namespace ephor::stripe {

struct StripeWorkcell {
  // The column 550 mm behind the scanned square's centre on -x, the shoulder
  // 450 mm above the table: every point of the square is 350-780 mm out, so
  // the flange can point straight down over all of it 380-430 mm up.
  Eigen::Isometry3d base_in_table = Eigen::Isometry3d(Eigen::Translation3d(-550.0, 0.0, 450.0));

  // Joint readings (nominal IK, the controller's own model) putting the
  // flange at `flange_in_table`, nearest `near` (rad); nullopt out of reach.
  // zero_offset_rad: the model's zero references (physical = reading +
  // offset), subtracted from the nominal IK's physical angles.
  std::optional<arm::Joints> joints_for(
      const Eigen::Isometry3d& flange_in_table, const arm::Joints& near,
      const arm::Joints& zero_offset_rad = arm::Joints::Zero()) const;
  // A configuration to start from: shoulder right, elbow up, wrist not
  // flipped, the flange pointing down over the square.
  static arm::Joints reference_joints();

  // From the work cell file the arm server reads too (deploy/stripe/
  // workcell.pbtxt, frame F of common/geometry/workcell.h): the table
  // frame is F moved to the centre of the field (F's working area), so the
  // scanned square is centred on the table frame's origin. The default
  // StripeWorkcell is the file with a 1100 x 1000 mm field and the column
  // at (0, 500) of F, 450 mm up.
  static StripeWorkcell from_workcell(const geometry::Workcell& cell);
  // The table frame's origin in F (mm): the field's centre on the table top.
  static Eigen::Vector3d table_origin_in_field(const geometry::Workcell& cell);
};

// Projector pose (projector -> table) looking straight down from `height_mm`
// above the table at (x, y), the stripe along the table direction at
// `stripe_azimuth_rad` (from +x, about +z).
Eigen::Isometry3d projector_looking_down(double x_mm, double y_mm, double height_mm,
                                         double stripe_azimuth_rad);

// Projector pose looking at `target` from `distance_mm` along the unit
// `approach` (from the target towards the sensor), the stripe's direction as
// near `stripe_hint` as the view allows.
Eigen::Isometry3d projector_looking_at(const Eigen::Vector3d& target,
                                       const Eigen::Vector3d& approach, double distance_mm,
                                       const Eigen::Vector3d& stripe_hint);

// The flange pose (table frame) that puts the projector at `projector_pose`
// given where the cage holds it (S_T of `cage`).
Eigen::Isometry3d flange_for_projector(const Eigen::Isometry3d& projector_pose,
                                       const SensorCalibration& cage);

// How long the PUMA needs between two joint readings at its speed limits,
// counted as the slowest joint's travel over its limit (s; no acceleration):
// a measure for ordering views, not a motion time.
double joint_travel_s(const arm::Joints& from, const arm::Joints& to);

// An order of `points` (joint readings) that travels little from `start`
// and back to it (an arm's rounds of views end where its work begins):
// greedily the nearest next, then improved by reversing stretches (2-opt)
// while that shortens the round in joint_travel_s. Returns the indices.
std::vector<size_t> short_round(const std::vector<arm::Joints>& points, const arm::Joints& start);

// Visits flange poses (table frame) from the joints `start`: each pose's
// joint readings nearest the previous ones (StripeWorkcell::joints_for with
// the model's zero references), unreachable poses left out. In the given
// order, or, with `least_travel`, in a short round (short_round) - for an
// arm that really moves between the views. Returns the poses' indices with
// their joint readings, in visiting order.
std::vector<std::pair<size_t, arm::Joints>> visiting_order(
    const StripeWorkcell& cell, const std::vector<Eigen::Isometry3d>& flanges_in_table,
    const arm::Joints& start, const arm::Joints& zero_offset_rad, bool least_travel);

struct RasterSpec {
  double x0_mm = -50.0, y0_mm = -50.0, x1_mm = 50.0, y1_mm = 50.0;  // region, table frame
  double step_mm = 10.0;          // between stripes (the paper's 10 mm)
  double height_mm = 300.0;       // projector above the table
  bool stripes_along_y = true;    // stripe direction; steps go across it
  double pass_length_mm = 120.0;  // stripe length used per pass (the camera sees ~140 mm)
};

// Projector poses of a boustrophedon raster covering the region: passes of
// pass_length along the stripe direction, stripes every step across it.
// Throws std::invalid_argument for a non-positive step or an empty region.
std::vector<Eigen::Isometry3d> raster_projector_poses(const RasterSpec& spec);

// A sweep of parallel stripes across `target` from one viewpoint (section 5's
// "direction of approach, direction of scan, and distance"): the projector
// looking at the target from `distance_mm` along `approach`, its stripe as
// near `stripe_hint` as the view allows, moved along the light plane's
// normal by -half_width .. +half_width in steps of step_mm.
std::vector<Eigen::Isometry3d> sweep_projector_poses(const Eigen::Vector3d& target,
                                                     const Eigen::Vector3d& approach,
                                                     double distance_mm,
                                                     const Eigen::Vector3d& stripe_hint,
                                                     double half_width_mm, double step_mm);

}  // namespace ephor::stripe
