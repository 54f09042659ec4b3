#include "procs/stripe/calibrate/calibration_run.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <spdlog/fmt/fmt.h>

namespace ephor::stripe {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Counts the images a step takes.
class CountingRig : public CalibrationRig {
 public:
  explicit CountingRig(CalibrationRig& rig) : rig_(rig) {}
  cv::Mat stripe_image(const arm::Joints& q) override {
    ++images;
    return rig_.stripe_image(q);
  }
  cv::Mat spot_image(const arm::Joints& q) override {
    ++images;
    return rig_.spot_image(q);
  }
  arm::Joints readings(const arm::Joints& commanded) const override {
    return rig_.readings(commanded);
  }
  int images = 0;

 private:
  CalibrationRig& rig_;
};

double angle_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() / kDeg;
}

}  // namespace

const char* to_string(CalibrationViews v) {
  return v == CalibrationViews::kFull ? "full" : "quick";
}

CalibrationViews parse_calibration_views(const std::string& name) {
  if (name == "full") return CalibrationViews::kFull;
  if (name == "quick") return CalibrationViews::kQuick;
  throw std::invalid_argument("views \"" + name + "\": want full or quick");
}

ZeroReferenceOptions zero_reference_options(const CalibrationRunOptions& o) {
  ZeroReferenceOptions z;
  z.spot_guess_mm = o.spot_guess_mm;
  z.working_branch_only = !o.all_branches;
  z.order_for_travel = true;
  if (o.views == CalibrationViews::kQuick) {
    z.distances_mm = {300.0};
    z.tilts_deg = {0.0, 30.0};
    z.rolls_deg = {0.0, 90.0};
    z.rounds = 1;
    z.min_views = 8;
  }
  return z;
}

std::vector<double> projector_heights_mm(const CalibrationRunOptions& o) {
  if (o.views == CalibrationViews::kQuick) return {300.0};
  return {250.0, 290.0, 330.0, 370.0};
}

CalibrationRefinerOptions refiner_options(const CalibrationRunOptions& o) {
  CalibrationRefinerOptions r;
  r.link_errors = o.link_errors;
  r.order_for_travel = true;
  if (o.views == CalibrationViews::kQuick) {
    r.centres_mm = {{0.0, 0.0}};
    r.distances_mm = {300.0};
    r.azimuths = 2;
    r.spot_distances_mm = {330.0};
    r.spot_azimuths = 4;
    r.spot_rolls_deg = {0.0};
    r.rows_step = 4;
  }
  return r;
}

CalibrationRunResult run_calibration(CalibrationRig& real_rig, const StripeWorkcell& cell,
                                     const StripeCalibration& start,
                                     const CalibrationRunOptions& options,
                                     const std::function<void(const std::string&)>& progress) {
  CountingRig rig(real_rig);
  CalibrationRunResult out;
  auto say = [&](std::string line) {
    if (progress) progress(line);
    out.report.push_back(std::move(line));
  };
  const Eigen::Vector2d spot = options.spot_guess_mm;

  // 1. Section 3: the zero references of joints 2-5, by the camera.
  const ZeroReferenceCalibrator zc(cell, zero_reference_options(options));
  int before = rig.images;
  out.zero = zc.calibrate(rig, start.arm_model(), start.sensor);
  const ZeroReferenceResult& z = out.zero;
  say(fmt::format(
      "zero references (section 3, by the camera): joints 2-5 corrected by {:+.4f} {:+.4f} {:+.4f} "
      "{:+.4f} deg; fit {:.3f} px rms (max {:.3f}) over {} sightings ({} lefty) in {} images; "
      "lefty-righty spot gap {:.2f} -> {:.2f} mm; the spot at ({:.2f}, {:.2f}) mm",
      z.correction_rad[1] / kDeg, z.correction_rad[2] / kDeg, z.correction_rad[3] / kDeg,
      z.correction_rad[4] / kDeg, z.rms_px, z.max_px, z.sightings, z.lefty_sightings,
      rig.images - before, z.lefty_righty_gap_before_mm, z.lefty_righty_gap_after_mm, z.spot_mm.x(),
      z.spot_mm.y()));
  TrueArm zeroed = TrueArm::with_zero_offsets(z.zero_offset_rad);
  {
    // Keep the start's link errors (an older file's) with the new zero references.
    ArmErrors e = start.arm;
    e.zero_offset_rad = z.zero_offset_rad;
    zeroed = TrueArm(e);
  }
  SensorCalibration cal = z.updated;

  // 2. The wrist (joint 6): C_T's turn about z6 in the fit above.
  {
    const Eigen::Matrix3d turn =
        start.sensor.camera_in_flange.linear() * z.updated.camera_in_flange.linear().transpose();
    // The turn's part about z6 (twist): the angle of its rotation of x6 about z6.
    const Eigen::Vector3d x = turn * Eigen::Vector3d::UnitX();
    const double about_z6 = std::atan2(x.y(), x.x()) / kDeg;
    say(fmt::format(
        "wrist (section 4, joint 6's zero reference): carried by C_T, turned {:+.3f} deg about z6 "
        "({:.3f} deg in all, {:.2f} mm) by the fit above",
        about_z6, angle_deg(start.sensor.camera_in_flange.linear(), cal.camera_in_flange.linear()),
        (start.sensor.camera_in_flange.translation() - cal.camera_in_flange.translation()).norm()));
  }

  // 3-4. Camera aim, then camera scale and roll: refinements of C_T and P
  // that the later steps supersede, so a step that cannot go on (the spot
  // lost) is reported and skipped, not the end of the calibration. The
  // quick views leave them out.
  if (options.views == CalibrationViews::kQuick) {
    say("camera aim, camera scale and roll (section 4): skipped (quick views; the projector "
        "plane and the joint refinement follow)");
  } else {
    before = rig.images;
    try {
      const CameraAimResult aim = calibrate_camera_aim(rig, cell, zeroed, cal, spot);
      cal = aim.updated;
      say(fmt::format(
          "camera aim (section 4): principal ray turned {:.4f} deg (the spot moved ({:+.2f}, "
          "{:+.2f}) px as the camera rose 100 mm; {} images)",
          aim.correction_deg, aim.spot_shift_px.x(), aim.spot_shift_px.y(), rig.images - before));
    } catch (const CalibrationError& e) {
      say(fmt::format("camera aim (section 4): skipped, C_T kept: {} ({} images)", e.what(),
                      rig.images - before));
    }
    before = rig.images;
    try {
      const CameraScaleRollResult scale =
          calibrate_camera_scale_and_roll(rig, cell, zeroed, cal, spot);
      cal = scale.updated;
      say(fmt::format(
          "camera scale and roll (section 4): magnification x {:.5f} (horizontal), x {:.5f} "
          "(vertical); roll {:+.4f} deg ({} images)",
          scale.fx_ratio, scale.fy_ratio, scale.roll_correction_deg, rig.images - before));
    } catch (const CalibrationError& e) {
      say(fmt::format("camera scale and roll (section 4): skipped, C_T and P kept: {} ({} images)",
                      e.what(), rig.images - before));
    }
  }

  // 5. Projector plane.
  before = rig.images;
  const ProjectorPlaneResult plane =
      calibrate_projector_plane(rig, cell, zeroed, cal, spot, projector_heights_mm(options));
  cal = plane.updated;
  say(fmt::format(
      "projector plane (section 4): normal turned {:.4f} deg, moved {:+.3f} mm; fit {:.3f} mm rms "
      "over {} points ({} images)",
      plane.normal_change_deg, plane.offset_change_mm, plane.rms_mm, plane.points,
      rig.images - before));

  // 6. The joint refinement (beyond the paper).
  before = rig.images;
  const CalibrationRefiner refiner(cell, refiner_options(options));
  out.refinement = refiner.refine(rig, zeroed, cal, z.sightings_used, z.spot_mm);
  const CalibrationRefinement& f = out.refinement;
  const arm::Joints dz = f.zero_offset_rad - z.zero_offset_rad;
  say(fmt::format(
      "joint refinement (Ceres; zero references, C_T, light plane{}): joints 2-5 moved {:+.4f} "
      "{:+.4f} {:+.4f} {:+.4f} deg, C_T {:.3f} mm / {:.4f} deg, light plane {:.4f} deg / {:.3f} "
      "mm; "
      "residual: spot {:.3f} -> {:.3f} px rms (max {:.3f}) over {} sightings, stripe on the table "
      "{:.3f} -> {:.3f} mm rms (max {:.3f}) over {} points in {} views ({} images); what it could "
      "not absorb stays in these residuals",
      options.link_errors ? ", links 1-5" : "", dz[1] / kDeg, dz[2] / kDeg, dz[3] / kDeg,
      dz[4] / kDeg, f.camera_change_mm, f.camera_change_deg, f.plane_change_deg, f.plane_change_mm,
      f.spot_rms_before_px, f.spot_rms_px, f.spot_max_px, f.spot_sightings, f.table_rms_before_mm,
      f.table_rms_mm, f.table_max_mm, f.stripe_points, f.stripe_views, rig.images - before));

  out.views = rig.images;
  StripeCalibration& c = out.calibration;
  c.robot_seed = start.robot_seed;
  c.arm = f.arm.errors();
  c.sensor = f.updated;
  c.report = out.report;
  return out;
}

}  // namespace ephor::stripe
