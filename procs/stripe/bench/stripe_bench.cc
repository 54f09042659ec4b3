// ephor-bench-stripe: the light-stripe sensor's figures beside paper 004's
// (section 5): random error on a flat plate, stripes processed per second
// (image to 3-D points), whole-scene accuracy against the true surfaces,
// and, with a seeded imperfect robot, the direction-dependent error of a
// pyramid's apex before and after each calibration stage (sections 3 and
// 4), with the zero references, the camera and the projector found against
// the truth; the peer in the same run, OpenCV's hand-eye calibrations
// (calibrateHandEye, calibrateRobotWorldHandEye) for the camera's pose on
// the flange on the zero-reference step's own images (the dot target,
// DotTarget); and the stripes per second scanned with the arm moving
// through the processes (tools/ephor stripe scan).
//
//   ephor-bench-stripe [--json FILE] [--out-dir DIR] [--seed N] [--robot-seeds N]
//                      [--sections random,scene,direction,scan]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/config/repo_paths.h"
#include "common/stripe/calibration_refiner.h"
#include "common/stripe/cloud_file.h"
#include "common/stripe/direction_error.h"
#include "common/stripe/dot_target.h"
#include "common/stripe/hand_eye_peer.h"
#include "common/stripe/plane_fit.h"
#include "common/stripe/sensor_calibrator.h"
#include "common/stripe/stripe_scan.h"
#include "common/stripe/zero_reference_calibrator.h"

namespace ephor::stripe {
namespace {

// Paper 004's figures (Agin 1985).
namespace paper {
// Section 5: "The random error in our data appears to be on the order of +-1 mm."
constexpr double kRandomErrorMm = 1.0;
// Section 5: "The worst direction-dependent errors we have measured appear to
// be on the order of +-5 mm."
constexpr double kDirectionErrorMm = 5.0;
// Section 5: "should be able to image 3 or 4 stripes of 256 three-dimensional
// points per second if scanning is done in a regular raster" (the paper's
// estimate with arm motion; its image preprocessing alone was "a few hundred
// milliseconds" a stripe).
constexpr double kStripesPerSecond = 3.5;
constexpr double kPreprocessingS = 0.3;
// Section 5: figure 4-1 was scanned "in 10 mm steps".
constexpr double kStepMm = 10.0;
}  // namespace paper

// Issue 16's targets.
namespace target {
constexpr double kRandomErrorMm = 0.3;     // 1 sigma point-to-plane
constexpr double kDirectionErrorMm = 1.0;  // worst, after calibration
}  // namespace target

constexpr double kPi = std::numbers::pi;

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double idx = p / 100.0 * static_cast<double>(v.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(idx));
  const size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (idx - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

std::string scene_path(const std::string& dir, const std::string& name) {
  return resolve_repo_path(dir + "/" + name + ".obj");
}

// A: the flat plate scanned with parallel stripes by the ideal robot; the
// band's thickness per centre method; B: the time from image to 3-D points.
nlohmann::json random_error_and_speed(const std::string& scenes, std::uint64_t seed,
                                      const std::string& out_dir) {
  const StripeScene scene = StripeScene::load(scene_path(scenes, "flat_plate"));
  const StripeWorld world(scene, StripeWorkcell{}, RobotTruth::ideal());
  RasterSpec spec;
  spec.x0_mm = -100;
  spec.x1_mm = 100;
  spec.y0_mm = -60;
  spec.y1_mm = 60;
  spec.step_mm = paper::kStepMm;
  spec.height_mm = 320;  // 300 mm above the plate's top, the paper's working range
  // The sensor pitched 4 deg along the stripe and rolled 3 deg across it
  // (the paper's plate was surely not square to it): the stripe then
  // slants across the pixel columns and the range varies along it, so
  // digitisation shows as it would; square on, every row would see the same
  // sub-pixel phase and the run centre's error would be a constant offset.
  auto poses = raster_projector_poses(spec);
  for (auto& p : poses)
    p = p * Eigen::AngleAxisd(4.0 * kPi / 180.0, Eigen::Vector3d::UnitX()) *
        Eigen::AngleAxisd(3.0 * kPi / 180.0, Eigen::Vector3d::UnitY());
  nlohmann::json out;
  std::printf(
      "Random error (section 5): flat plate, %zu parallel stripes %.0f mm apart, "
      "300 mm range, sensor tilted 4 and 3 deg, ideal robot\n",
      poses.size(), spec.step_mm);
  std::printf("  %-9s %9s %9s %8s %12s %14s\n", "centre", "1sigma_mm", "max_mm", "points",
              "stripes/s", "cpu_us/stripe");
  for (CentreMethod m : {CentreMethod::kRunCentre, CentreMethod::kCentroid, CentreMethod::kGaussian,
                         CentreMethod::kSteger}) {
    StripeExtractorOptions eo;
    eo.method = m;
    const RangeFinder finder(StripeWorkcell{}, TrueArm::nominal(),
                             SensorCalibration::drawing_cage(), eo);
    const ScanResult r = run_scan(world, finder, poses, seed);
    const auto cloud = r.cloud();
    const auto fit = PlaneFit::fit(cloud);
    // Speed: image -> 3-D points again on the same images, several rounds.
    std::vector<cv::Mat> images;
    for (const auto& s : r.stripes) images.push_back(world.image(s.joints, seed));
    // Process CPU time, not wall time: the machine runs other real-time work.
    const int rounds = 20;
    size_t points = 0;
    const std::clock_t c0 = std::clock();
    for (int k = 0; k < rounds; ++k)
      for (size_t i = 0; i < images.size(); ++i)
        points += finder.measure(images[i], r.stripes[i].joints).size();
    const double s = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    const double per_stripe = s / static_cast<double>(rounds * images.size());
    const double rms = fit ? fit->rms_mm : -1.0, mx = fit ? fit->max_abs_mm : -1.0;
    std::printf("  %-9s %9.4f %9.4f %8zu %12.0f %14.1f\n", centre_method_name(m), rms, mx,
                cloud.size(), 1.0 / per_stripe, 1e6 * per_stripe);
    out["methods"][centre_method_name(m)] = {
        {"random_error_1sigma_mm", rms},
        {"max_abs_mm", mx},
        {"points", cloud.size()},
        {"stripes", r.stripes.size()},
        {"plate_height_mm", fit ? fit->centroid.z() : 0.0},
        {"stripes_per_s_processed", 1.0 / per_stripe},
        {"points_per_stripe", static_cast<double>(points) / (rounds * images.size())},
        {"render_s_per_stripe", r.render_s / static_cast<double>(r.stripes.size())}};
    if (m == CentreMethod::kGaussian && !out_dir.empty())
      save_cloud_ply(out_dir + "/flat_plate.ply", cloud);
  }
  out["paper_random_error_mm"] = paper::kRandomErrorMm;
  out["target_random_error_1sigma_mm"] = target::kRandomErrorMm;
  out["paper_stripes_per_s"] = paper::kStripesPerSecond;
  out["paper_preprocessing_s_per_stripe"] = paper::kPreprocessingS;
  std::printf(
      "  paper: +-%.0f mm band; target <= %.1f mm (1 sigma). Paper's speed: %.1f stripes/s"
      " (preprocessing ~%.1f s a stripe)\n",
      paper::kRandomErrorMm, target::kRandomErrorMm, paper::kStripesPerSecond,
      paper::kPreprocessingS);
  return out;
}

// C: every cloud point's distance to the scene's true surface.
nlohmann::json whole_scene(const std::string& scenes, std::uint64_t seed,
                           const std::string& out_dir) {
  struct Job {
    const char* name;
    RasterSpec spec;
  };
  std::vector<Job> jobs = {
      {"flat_plate", RasterSpec{-100, -60, 100, 60, paper::kStepMm, 320, true, 120}},
      {"pyramid", RasterSpec{-80, -70, 80, 70, paper::kStepMm, 300, true, 70}},
      {"cup_spoon", RasterSpec{-60, -60, 140, 60, paper::kStepMm, 330, true, 60}},
  };
  nlohmann::json out;
  std::printf(
      "Whole-scene accuracy: distance of every cloud point to the true surface, ideal "
      "robot, 10 mm raster\n");
  std::printf("  %-11s %8s %8s %8s %8s %8s\n", "scene", "stripes", "points", "p50_mm", "p99_mm",
              "max_mm");
  for (const Job& j : jobs) {
    const StripeScene scene = StripeScene::load(scene_path(scenes, j.name));
    const StripeWorld world(scene, StripeWorkcell{}, RobotTruth::ideal());
    const RangeFinder finder(StripeWorkcell{}, TrueArm::nominal(),
                             SensorCalibration::drawing_cage());
    const ScanResult r = run_scan(world, finder, raster_projector_poses(j.spec), seed);
    const auto cloud = r.cloud();
    std::vector<double> d;
    d.reserve(cloud.size());
    for (const auto& p : cloud) d.push_back(scene.distance_to_surface(p));
    const double p50 = percentile(d, 50), p99 = percentile(d, 99), mx = percentile(d, 100);
    std::printf("  %-11s %8zu %8zu %8.3f %8.3f %8.3f\n", j.name, r.stripes.size(), cloud.size(),
                p50, p99, mx);
    out[j.name] = {{"stripes", r.stripes.size()},
                   {"points", cloud.size()},
                   {"unreachable", r.unreachable},
                   {"p50_mm", p50},
                   {"p99_mm", p99},
                   {"max_mm", mx}};
    if (!out_dir.empty()) save_cloud_ply(out_dir + "/" + j.name + ".ply", cloud);
  }
  return out;
}

// A rig that keeps the filter-removed images it takes (with their joint
// readings) while `recording`: the zero-reference step's views, for the
// hand-eye peer, which then works on the very images our fit used.
class RecordingRig : public CalibrationRig {
 public:
  explicit RecordingRig(CalibrationRig& inner) : inner_(&inner) {}
  cv::Mat stripe_image(const arm::Joints& q) override { return inner_->stripe_image(q); }
  cv::Mat spot_image(const arm::Joints& q) override {
    cv::Mat image = inner_->spot_image(q);
    if (recording) taken.push_back({inner_->readings(q), image});
    return image;
  }
  arm::Joints readings(const arm::Joints& commanded) const override {
    return inner_->readings(commanded);
  }
  struct Taken {
    arm::Joints readings;
    cv::Mat image;
  };
  bool recording = false;
  std::vector<Taken> taken;

 private:
  CalibrationRig* inner_;
};

double rotation_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180 / kPi;
}

// The camera's true pose on the flange as an arm model whose joint 6 zero
// reference is model_zero6 (rad) and whose link 6 is the drawing's can see
// it: link 6's true zero-reference and DH errors folded in.
Eigen::Isometry3d camera_seen_by(const RobotTruth& truth, double model_zero6) {
  const arm::DhLink& l6 = truth.arm.errors().dh_error[5];
  const Eigen::Isometry3d e6 =
      Eigen::AngleAxisd(truth.arm.errors().zero_offset_rad[5] - model_zero6,
                        Eigen::Vector3d::UnitZ()) *
      Eigen::Translation3d(l6.a_mm, 0.0, l6.d_mm) *
      Eigen::AngleAxisd(l6.alpha_rad, Eigen::Vector3d::UnitX());
  return e6 * truth.cage.camera_in_flange;
}

// D: the pyramid's apex from 20 views (section 5) by robots whose arm and
// cage differ from the nominal model (per robot seed), after each stage of
// calibration: the nominal model (none), section 4 alone, section 3's zero
// references found by ZeroReferenceCalibrator and then section 4's steps,
// and, for comparison, the true zero references handed over (an oracle).
// Every calibration runs on the empty table (its spot at the origin)
// through the rig, with image noise; the figures are on the pyramid.
nlohmann::json direction_dependent(const std::string& scenes, std::uint64_t seed, int robot_seeds,
                                   nlohmann::json& calibration, nlohmann::json& calibration_refined,
                                   nlohmann::json& hand_eye) {
  const StripeScene scene = StripeScene::load(scene_path(scenes, "pyramid"));
  const Eigen::Vector3d apex(0, 0, 60);
  const auto views = section5_views();
  nlohmann::json out = nlohmann::json::array();
  std::printf(
      "Direction-dependent error (section 5): pyramid apex from %zu views (approach "
      "down / tilted 25 deg from +-x, +-y; stripes along x / y; 270 / 330 mm)\n",
      views.size());
  std::printf("  %-10s %-44s %8s %14s %14s %9s %9s %9s %9s %9s\n", "robot", "model", "located",
              "worst_shift_mm", "worst_abs_mm", "cam_deg", "cam_rot", "cam_mm", "plane_deg",
              "plane_mm");
  const StripeScene table;  // calibration on the empty table, its spot at the origin
  const Eigen::Vector2d spot(0, 0);
  const StripeWorkcell cell;
  // The dot target printed around the spot, for the hand-eye peer; the
  // spot's sightings are the same with it (DotTarget).
  const DotTarget target(spot);
  StripeRendererOptions table_options;
  table_options.dots_mm = target.dots_in_table();
  table_options.dot_radii_mm = target.dot_radii_mm();
  struct ZeroRow {
    int robot_seed;
    arm::Joints truth, found;
    ZeroReferenceResult result;
    double camera_mm, camera_deg;
  };
  std::vector<ZeroRow> zero_rows;
  struct RefineRow {
    int robot_seed;
    bool links;
    arm::Joints truth;
    double camera_mm, camera_deg, plane_deg, plane_mm;
    CalibrationRefinement result;
  };
  std::vector<RefineRow> refinements;
  for (int rs = 0; rs <= robot_seeds; ++rs) {
    const RobotTruth truth = rs == 0 ? RobotTruth::ideal() : RobotTruth::draw(rs);
    const StripeWorld world(scene, cell, truth);
    const StripeWorld bench_table(table, cell, truth, table_options);
    SimulatedRig sim_rig(bench_table, seed + 1000);
    RecordingRig rig(sim_rig);
    const std::string robot = rs == 0 ? "ideal" : "seed " + std::to_string(rs);
    nlohmann::json j = {{"robot_seed", rs}, {"views", views.size()}};
    for (double z : truth.arm.errors().zero_offset_rad)
      j["true_zero_offset_deg"].push_back(z * 180 / kPi);
    // The camera as the software can know it: joint 6's zero-reference
    // error folded into C_T (no camera measurement separates them).
    const Eigen::Isometry3d true_camera =
        Eigen::Isometry3d(
            Eigen::AngleAxisd(truth.arm.errors().zero_offset_rad[5], Eigen::Vector3d::UnitZ())) *
        truth.cage.camera_in_flange;
    // The cage as a model with its own joint 6 zero reference sees it.
    auto seen = [&](const TrueArm& model, const Eigen::Isometry3d& in_flange) {
      return Eigen::Isometry3d(Eigen::AngleAxisd(
                 truth.arm.errors().zero_offset_rad[5] - model.errors().zero_offset_rad[5],
                 Eigen::Vector3d::UnitZ())) *
             in_flange;
    };
    auto row = [&](const std::string& name, const TrueArm& model, const SensorCalibration& cal,
                   const nlohmann::json& correction) {
      const RangeFinder finder(cell, model, cal);
      const DirectionError e = measure_direction_error(world, finder, views, apex, seed);
      const Eigen::Isometry3d tc = seen(model, truth.cage.camera_in_flange);
      const Eigen::Isometry3d tp = seen(model, truth.cage.projector_in_flange);
      const double cam_axis_err =
          std::acos(
              std::clamp(cal.camera_in_flange.linear().col(2).dot(tc.linear().col(2)), -1.0, 1.0)) *
          180 / kPi;
      // The whole turn (axis and roll about it), not only the axis.
      const double cam_rot_err =
          Eigen::AngleAxisd(cal.camera_in_flange.linear().transpose() * tc.linear()).angle() * 180 /
          kPi;
      const double plane_err =
          std::acos(
              std::clamp(std::abs(cal.projector_in_flange.linear().col(0).dot(tp.linear().col(0))),
                         -1.0, 1.0)) *
          180 / kPi;
      // Positions: the camera's centre, and the believed projector origin's
      // distance from the true light plane (flange frame, mm).
      const double cam_pos_err = (cal.camera_in_flange.translation() - tc.translation()).norm();
      const double plane_off_err = std::abs(
          tp.linear().col(0).dot(cal.projector_in_flange.translation() - tp.translation()));
      std::printf("  %-10s %-44s %5d/%-2zu %14.3f %14.3f %9.3f %9.3f %9.3f %9.3f %9.3f\n",
                  robot.c_str(), name.c_str(), e.located, views.size(), e.worst_from_mean_mm,
                  e.worst_from_truth_mm, cam_axis_err, cam_rot_err, cam_pos_err, plane_err,
                  plane_off_err);
      std::fflush(stdout);
      nlohmann::json apexes = nlohmann::json::array();
      for (size_t v = 0; v < views.size(); ++v)
        apexes.push_back(e.apex_mm[v] ? nlohmann::json{{"view", views[v].label},
                                                       {"x", e.apex_mm[v]->x()},
                                                       {"y", e.apex_mm[v]->y()},
                                                       {"z", e.apex_mm[v]->z()}}
                                      : nlohmann::json{{"view", views[v].label}});
      j["stages"].push_back({{"stage", name},
                             {"apex_mm", apexes},
                             {"correction", correction},
                             {"located", e.located},
                             {"unreachable_poses", e.unreachable_poses},
                             {"worst_shift_from_mean_mm", e.worst_from_mean_mm},
                             {"worst_from_true_apex_mm", e.worst_from_truth_mm},
                             {"camera_axis_error_deg", cam_axis_err},
                             {"camera_rotation_error_deg", cam_rot_err},
                             {"camera_position_error_mm", cam_pos_err},
                             {"light_plane_normal_error_deg", plane_err},
                             {"light_plane_offset_error_mm", plane_off_err}});
    };
    auto failed = [&](const std::string& name, const CalibrationError& e) {
      std::printf("  %-10s %-44s failed: %s\n", robot.c_str(), name.c_str(), e.what());
      j["stages"].push_back({{"stage", name}, {"error", e.what()}});
    };
    // Section 4's steps from `cal` on the arm `model`, each a row.
    auto section4 = [&](const std::string& prefix, const TrueArm& model, SensorCalibration cal,
                        bool aim, bool scale) -> SensorCalibration {
      std::string name = prefix;
      try {
        if (aim) {
          const CameraAimResult a = calibrate_camera_aim(rig, cell, model, cal, spot);
          cal = a.updated;
          name += " + camera aim";
          row(name, model, cal, {{"camera_aim_correction_deg", a.correction_deg}});
        }
        if (scale) {
          const CameraScaleRollResult c =
              calibrate_camera_scale_and_roll(rig, cell, model, cal, spot);
          cal = c.updated;
          name += " + scale/roll";
          row(name, model, cal,
              {{"fx_ratio", c.fx_ratio},
               {"fy_ratio", c.fy_ratio},
               {"roll_correction_deg", c.roll_correction_deg}});
        }
        const ProjectorPlaneResult pp = calibrate_projector_plane(rig, cell, model, cal, spot);
        cal = pp.updated;
        name += " + projector plane";
        row(name, model, cal,
            {{"plane_normal_change_deg", pp.normal_change_deg},
             {"plane_offset_change_mm", pp.offset_change_mm},
             {"plane_fit_rms_mm", pp.rms_mm}});
      } catch (const CalibrationError& e) {
        failed(name + " (next step)", e);
      }
      return cal;
    };
    // The peer: OpenCV's hand-eye methods on the zero-reference step's own
    // images (every arm branch), those where the whole dot target is seen;
    // the flange poses from the joint readings through an arm model: the
    // nominal one (all a peer has), ours (the zero references found), the
    // true zero references (an oracle) and the true arm (links too: what
    // the peer's methods and PnP alone leave).
    nlohmann::json he = {{"robot_seed", rs}};
    auto hand_eye_peer = [&](const ZeroReferenceResult& z) {
      std::vector<std::pair<arm::Joints, Eigen::Isometry3d>> sighted;
      std::vector<double> rms;
      for (const RecordingRig::Taken& t : rig.taken)
        if (const auto s = target.find(t.image, SensorCalibration::drawing_cage().camera)) {
          sighted.push_back({t.readings, s->target_in_camera});
          rms.push_back(s->rms_px);
        }
      he["images"] = rig.taken.size();
      he["spot_sightings"] = z.sightings;
      he["target_views"] = sighted.size();
      he["pnp_rms_px_p50"] = percentile(rms, 50);
      he["pnp_rms_px_max"] = percentile(rms, 100);
      struct Kinematics {
        const char* name;
        TrueArm arm;
        double zero6;
      };
      const std::vector<Kinematics> models = {
          {"nominal", TrueArm::nominal(), 0.0},
          {"our zero refs", TrueArm::with_zero_offsets(z.zero_offset_rad), 0.0},
          {"true zero refs", TrueArm::with_zero_offsets(truth.arm.errors().zero_offset_rad),
           truth.arm.errors().zero_offset_rad[5]},
          {"true arm", truth.arm, 0.0}};
      for (const Kinematics& k : models) {
        std::vector<HandEyeView> all;
        for (const auto& [q, t] : sighted) all.push_back({k.arm.flange(q), t});
        const bool exact = std::string(k.name) == "true arm";
        const Eigen::Isometry3d want =
            exact ? truth.cage.camera_in_flange : camera_seen_by(truth, k.zero6);
        // Every target view, and the largest set within 120 deg of each
        // other (views_within: what TSAI and DANIILIDIS need).
        std::vector<HandEyeView> within = views_within(all, 120.0);
        he["views_within_120_deg"] = within.size();
        for (const auto& [set, v] : {std::pair{"all", &all}, std::pair{"within 120 deg", &within}})
          for (HandEyeMethod m : kHandEyeMethods) {
            nlohmann::json r = {{"method", hand_eye_method_name(m)},
                                {"kinematics", k.name},
                                {"views", set},
                                {"view_count", v->size()}};
            try {
              const auto c0 = std::chrono::steady_clock::now();
              const Eigen::Isometry3d got = solve_hand_eye(*v, m);
              r["ms"] =
                  std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - c0)
                      .count();
              r["position_error_mm"] = (got.translation() - want.translation()).norm();
              r["rotation_error_deg"] = rotation_deg(got, want);
            } catch (const std::exception& e) {
              r["error"] = e.what();
            }
            he["peer"].push_back(r);
          }
      }
    };
    const SensorCalibration drawing = SensorCalibration::drawing_cage();
    row("nominal arm, drawing cage", TrueArm::nominal(), drawing, {});
    if (rs == 0) {
      out.push_back(j);
      continue;
    }
    section4("nominal arm", TrueArm::nominal(), drawing, true, false);
    // Section 3 by the camera, then section 4's steps in the paper's order
    // (on the drawing cage), and section 4's projector step on the C_T the
    // zero-reference fit found with the joints.
    try {
      const ZeroReferenceCalibrator zc(cell);
      rig.recording = true;
      const ZeroReferenceResult z = zc.calibrate(rig, TrueArm::nominal(), drawing);
      rig.recording = false;
      const TrueArm zeroed = TrueArm::with_zero_offsets(z.zero_offset_rad);
      const Eigen::Isometry3d& fc = z.updated.camera_in_flange;
      zero_rows.push_back(
          {rs, truth.arm.errors().zero_offset_rad, z.zero_offset_rad, z,
           (fc.translation() - true_camera.translation()).norm(),
           Eigen::AngleAxisd(fc.linear().transpose() * true_camera.linear()).angle() * 180 / kPi});
      nlohmann::json zj = {{"rms_px", z.rms_px},
                           {"sightings", z.sightings},
                           {"lefty_righty_gap_before_mm", z.lefty_righty_gap_before_mm},
                           {"lefty_righty_gap_after_mm", z.lefty_righty_gap_after_mm}};
      for (int k = 0; k < 6; ++k) zj["correction_deg"].push_back(z.correction_rad[k] * 180 / kPi);
      row("zero refs, drawing cage", zeroed, drawing, zj);
      const SensorCalibration paper_sequence = section4("zero refs", zeroed, drawing, true, true);
      he["ours"].push_back(
          {{"method", "paper's sequence: zero refs by the camera, camera aim, scale/roll"},
           {"position_error_mm", (paper_sequence.camera_in_flange.translation() -
                                  camera_seen_by(truth, 0.0).translation())
                                     .norm()},
           {"rotation_error_deg",
            rotation_deg(paper_sequence.camera_in_flange, camera_seen_by(truth, 0.0))}});
      he["ours"].push_back(
          {{"method", "zero-reference fit (section 3 by the camera, C_T in 6 dof)"},
           {"position_error_mm",
            (z.updated.camera_in_flange.translation() - camera_seen_by(truth, 0.0).translation())
                .norm()},
           {"rotation_error_deg",
            rotation_deg(z.updated.camera_in_flange, camera_seen_by(truth, 0.0))}});
      hand_eye_peer(z);
      row("zero refs, fitted C_T", zeroed, z.updated, zj);
      // Section 4's projector step on the fitted C_T, then one refinement
      // of everything over the spot sightings and stripes on the table.
      SensorCalibration cal = z.updated;
      try {
        const ProjectorPlaneResult pp = calibrate_projector_plane(rig, cell, zeroed, cal, spot);
        cal = pp.updated;
        row("zero refs, fitted C_T + projector plane", zeroed, cal,
            {{"plane_normal_change_deg", pp.normal_change_deg},
             {"plane_offset_change_mm", pp.offset_change_mm},
             {"plane_fit_rms_mm", pp.rms_mm}});
        // The paper's model (zero references) and one with the links too.
        for (bool links : {false, true}) {
          CalibrationRefinerOptions ro;
          ro.link_errors = links;
          const CalibrationRefiner refiner(cell, ro);
          const CalibrationRefinement f =
              refiner.refine(rig, zeroed, cal, z.sightings_used, z.spot_mm);
          nlohmann::json fj = {{"link_errors", links},
                               {"spot_rms_before_px", f.spot_rms_before_px},
                               {"spot_rms_px", f.spot_rms_px},
                               {"spot_max_px", f.spot_max_px},
                               {"table_rms_before_mm", f.table_rms_before_mm},
                               {"table_rms_mm", f.table_rms_mm},
                               {"table_max_mm", f.table_max_mm},
                               {"stripe_views", f.stripe_views},
                               {"stripe_points", f.stripe_points},
                               {"camera_change_mm", f.camera_change_mm},
                               {"camera_change_deg", f.camera_change_deg},
                               {"plane_change_deg", f.plane_change_deg},
                               {"plane_change_mm", f.plane_change_mm}};
          for (int k = 0; k < 6; ++k)
            fj["correction_deg"].push_back(f.correction_rad[k] * 180 / kPi);
          row(links ? "+ refinement with link errors" : "+ refinement (zero refs, C_T, plane)",
              f.arm, f.updated, fj);
          he["ours"].push_back(
              {{"method", links ? "Ceres refinement with links 1-5"
                                : "Ceres refinement (zero refs, C_T, light plane)"},
               {"position_error_mm", (f.updated.camera_in_flange.translation() -
                                      camera_seen_by(truth, 0.0).translation())
                                         .norm()},
               {"rotation_error_deg",
                rotation_deg(f.updated.camera_in_flange, camera_seen_by(truth, 0.0))}});
          // Against the truth as the refined model can see it: link 6 (its
          // zero reference and DH errors) goes into C_T and S_T.
          const arm::DhLink& l6 = truth.arm.errors().dh_error[5];
          const Eigen::Isometry3d e6 =
              Eigen::AngleAxisd(truth.arm.errors().zero_offset_rad[5], Eigen::Vector3d::UnitZ()) *
              Eigen::Translation3d(l6.a_mm, 0.0, l6.d_mm) *
              Eigen::AngleAxisd(l6.alpha_rad, Eigen::Vector3d::UnitX());
          const Eigen::Isometry3d tc = e6 * truth.cage.camera_in_flange;
          const Eigen::Isometry3d tp = e6 * truth.cage.projector_in_flange;
          const Eigen::Isometry3d& rc = f.updated.camera_in_flange;
          const Eigen::Isometry3d& fp = f.updated.projector_in_flange;
          const Eigen::Vector3d n = tp.linear().col(0);
          refinements.push_back(
              {rs, links, truth.arm.errors().zero_offset_rad,
               (rc.translation() - tc.translation()).norm(),
               Eigen::AngleAxisd(rc.linear().transpose() * tc.linear()).angle() * 180 / kPi,
               std::acos(std::clamp(std::abs(fp.linear().col(0).dot(n)), -1.0, 1.0)) * 180 / kPi,
               std::abs(n.dot(fp.translation() - tp.translation())), f});
        }
      } catch (const CalibrationError& e) {
        failed("zero refs, fitted C_T + plane / refinement", e);
      }
    } catch (const CalibrationError& e) {
      failed("zero references", e);
    }
    const TrueArm oracle = TrueArm::with_zero_offsets(truth.arm.errors().zero_offset_rad);
    row("oracle zero refs, drawing cage", oracle, drawing, {});
    section4("oracle zero refs", oracle, drawing, true, false);
    out.push_back(j);
    if (!he["ours"].empty()) hand_eye.push_back(he);
  }
  std::printf("  paper: worst +-%.0f mm; target <= %.0f mm worst after calibration\n",
              paper::kDirectionErrorMm, target::kDirectionErrorMm);

  // The zero references found (section 3) against the truth, per joint.
  std::printf(
      "Calibration (section 3): zero references found by the camera (%s) vs the truth, deg;"
      " joint 6 goes into C_T\n",
      "spot sightings from every arm branch, image noise on");
  std::printf("  %-8s %5s %9s %9s %9s   %s\n", "robot", "joint", "true_deg", "found_deg",
              "error_deg", "");
  calibration = nlohmann::json::array();
  for (const ZeroRow& z : zero_rows) {
    nlohmann::json c = {{"robot_seed", z.robot_seed}};
    double worst = 0.0;
    for (int k = 1; k < 5; ++k) {
      const double t = z.truth[k] * 180 / kPi, f = z.found[k] * 180 / kPi;
      worst = std::max(worst, std::abs(f - t));
      std::printf("  seed %-3d %5d %9.4f %9.4f %9.4f\n", z.robot_seed, k + 1, t, f, f - t);
      c["joints"].push_back({{"joint", k + 1}, {"true_deg", t}, {"found_deg", f}});
    }
    std::printf("  seed %-3d %5d %9.4f %9s (in C_T)\n", z.robot_seed, 6, z.truth[5] * 180 / kPi,
                "-");
    std::printf(
        "  seed %-3d worst %.4f deg; camera pose (joint 6 folded in) off %.3f mm / %.4f deg;"
        " fit %.3f px rms over %zu sightings (%d lefty); lefty-righty spot gap %.2f -> %.3f mm;"
        " condition %.0f\n",
        z.robot_seed, worst, z.camera_mm, z.camera_deg, z.result.rms_px, z.result.sightings,
        z.result.lefty_sightings, z.result.lefty_righty_gap_before_mm,
        z.result.lefty_righty_gap_after_mm, z.result.condition);
    c["worst_error_deg"] = worst;
    c["joint6_true_deg"] = z.truth[5] * 180 / kPi;
    c["camera_position_error_mm"] = z.camera_mm;
    c["camera_rotation_error_deg"] = z.camera_deg;
    c["rms_px"] = z.result.rms_px;
    c["sightings"] = z.result.sightings;
    c["lefty_righty_gap_before_mm"] = z.result.lefty_righty_gap_before_mm;
    c["lefty_righty_gap_after_mm"] = z.result.lefty_righty_gap_after_mm;
    calibration.push_back(c);
  }
  std::printf("  paper: repeatability +-0.1 deg; target <= 0.02 deg\n");
  std::printf(
      "Joint refinement (beyond the paper): zero refs 2-5 + C_T + light plane + spot (+ links"
      " 1-5's d, a, alpha) over the spot sightings and the stripe on the table\n");
  for (const RefineRow& f : refinements) {
    const CalibrationRefinement& r = f.result;
    double worst = 0.0;
    std::printf("  seed %-3d %-10s joints 2-5 error deg:", f.robot_seed,
                f.links ? "+ links" : "zero refs");
    nlohmann::json c = {{"robot_seed", f.robot_seed}, {"link_errors", f.links}};
    for (int k = 1; k < 5; ++k) {
      const double e = (r.zero_offset_rad[k] - f.truth[k]) * 180 / kPi;
      worst = std::max(worst, std::abs(e));
      std::printf(" %+.4f", e);
      c["zero_ref_error_deg"].push_back(e);
    }
    std::printf(
        " (worst %.4f)\n                     residual: spot %.3f -> %.3f px rms (max %.3f) over %zu"
        " sightings; table %.3f -> %.3f mm rms (max %.3f) over %zu points in %zu views\n",
        worst, r.spot_rms_before_px, r.spot_rms_px, r.spot_max_px, r.spot_sightings,
        r.table_rms_before_mm, r.table_rms_mm, r.table_max_mm, r.stripe_points, r.stripe_views);
    c["worst_error_deg"] = worst;
    c["spot_rms_px"] = r.spot_rms_px;
    c["table_rms_mm"] = r.table_rms_mm;
    std::printf(
        "                     C_T off the truth %.3f mm / %.4f deg; light plane %.4f deg /"
        " %.3f mm (link 6 folded in)\n",
        f.camera_mm, f.camera_deg, f.plane_deg, f.plane_mm);
    c["camera_position_error_mm"] = f.camera_mm;
    c["camera_rotation_error_deg"] = f.camera_deg;
    c["light_plane_normal_error_deg"] = f.plane_deg;
    c["light_plane_offset_error_mm"] = f.plane_mm;
    calibration_refined.push_back(c);
  }
  std::printf(
      "Camera on the flange against the truth (link 6 folded in): OpenCV's hand-eye peers on the"
      " zero-reference step's images with the whole dot target in view (PnP), flange poses by"
      " each arm model; ours beside them\n");
  for (const nlohmann::json& h : hand_eye) {
    std::printf(
        "  seed %-3d %zu images, %zu spot sightings, %zu target views (PnP rms p50 %.3f px)\n",
        h["robot_seed"].get<int>(), h.value("images", size_t{0}),
        h.value("spot_sightings", size_t{0}), h.value("target_views", size_t{0}),
        h.value("pnp_rms_px_p50", 0.0));
    std::string kin;
    for (const nlohmann::json& r : h.value("peer", nlohmann::json::array())) {
      const std::string here = r["kinematics"].get<std::string>() + ", " +
                               r["views"].get<std::string>() + " (" +
                               std::to_string(r["view_count"].get<size_t>()) + " views)";
      if (here != kin) {
        kin = here;
        std::printf("    peer, %s arm model:\n", kin.c_str());
      }
      if (r.contains("error"))
        std::printf("      %-12s failed: %s\n", r["method"].get<std::string>().c_str(),
                    r["error"].get<std::string>().c_str());
      else
        std::printf("      %-12s %8.3f mm %8.4f deg\n", r["method"].get<std::string>().c_str(),
                    r["position_error_mm"].get<double>(), r["rotation_error_deg"].get<double>());
    }
    for (const nlohmann::json& r : h["ours"])
      std::printf("    ours: %-66s %8.3f mm %8.4f deg\n", r["method"].get<std::string>().c_str(),
                  r["position_error_mm"].get<double>(), r["rotation_error_deg"].get<double>());
  }
  return out;
}

// E: stripes per second scanned with the arm moving, through the processes
// (tools/ephor stripe scan: the simulator, stripe, range, planner, comm and
// the shared arm, headless): the flat plate's 9-stripe raster and the
// pyramid's 51 stripes in 3 passes; each scan's summary as the planner
// wrote it. The scan's speed is the arm's (procs/stripe/README.md).
nlohmann::json scanned_speed(const std::string& scenes, const std::string& out_dir) {
  struct Job {
    const char* name;
    const char* region;
  };
  const std::vector<Job> jobs = {{"flat_plate", "-40,-30,40,30"}, {"pyramid", "-80,-70,80,70"}};
  const std::filesystem::path tmp =
      std::filesystem::temp_directory_path() /
      ("ephor-bench-stripe-" + std::to_string(static_cast<long>(::getpid())));
  std::filesystem::create_directories(tmp);
  nlohmann::json out;
  bool ok = true;
  std::printf(
      "Stripes per second scanned with the arm moving (tools/ephor stripe scan, the processes"
      " headless, robot seed 0, 10 mm steps)\n");
  std::printf("  %-11s %8s %8s %10s %12s %10s %14s\n", "scene", "stripes", "points", "elapsed_s",
              "stripes/s", "motion_s", "cpu_us/stripe");
  for (const Job& j : jobs) {
    const std::string summary = (tmp / (std::string(j.name) + ".json")).string();
    const std::string cloud = out_dir.empty() ? (tmp / (std::string(j.name) + ".ply")).string()
                                              : out_dir + "/" + j.name + "_scanned.ply";
    const std::string cmd = "'" + resolve_repo_path("tools/ephor") + "' stripe scan --scene '" +
                            scene_path(scenes, j.name) + "' --region=" + j.region +
                            " --step-mm 10 --out '" + cloud + "' --summary '" + summary + "' > '" +
                            (tmp / "scan.log").string() + "' 2>&1";
    const int rc = std::system(cmd.c_str());
    nlohmann::json r;
    if (std::FILE* f = std::fopen(summary.c_str(), "r")) {
      r = nlohmann::json::parse(f, nullptr, false);
      std::fclose(f);
    }
    if (r.is_discarded() || !r.is_object()) r = nlohmann::json::object();
    r["exit_status"] = rc;
    if (rc != 0 || r.value("state", "") != "done") {
      const std::string why = r.value("reason", "no summary (see " + cmd + ")");
      std::printf("  %-11s failed after %d of %d stripes: %s\n", j.name,
                  r.value("stripes_captured", 0), r.value("stripes_planned", 0), why.c_str());
      ok = false;
    } else {
      std::printf("  %-11s %8d %8d %10.2f %12.2f %10.2f %14.0f\n", j.name,
                  r.value("stripes_captured", 0), r.value("cloud_points", 0),
                  r.value("elapsed_s", 0.0), r.value("stripes_per_s_scanned", 0.0),
                  r.value("motion_s", 0.0), r.value("processing_cpu_us_per_stripe", 0.0));
    }
    out[j.name] = r;
  }
  // The scans' log stays for a failed scan.
  if (ok) std::filesystem::remove_all(tmp);
  out["paper_stripes_per_s"] = paper::kStripesPerSecond;
  std::printf("  paper: %.1f stripes/s with arm motion (\"3 or 4\")\n", paper::kStripesPerSecond);
  return out;
}

}  // namespace
}  // namespace ephor::stripe

int main(int argc, char** argv) {
  using namespace ephor::stripe;
  CLI::App app{"ephor-bench-stripe: paper 004's figures (section 5) on this machine"};
  std::string json_path, out_dir, scenes = "deploy/stripe/scenes",
                                  sections = "random,scene,direction,scan";
  std::uint64_t seed = 1;
  int robot_seeds = 3;
  app.add_option("--json", json_path, "write the results as JSON");
  app.add_option("--out-dir", out_dir, "write the scanned clouds as PLY files here");
  app.add_option("--scenes", scenes, "folder of the scene OBJ files");
  app.add_option("--seed", seed, "first image-noise seed");
  app.add_option("--sections", sections,
                 "which parts to run, comma-separated: random, scene, direction (with the"
                 " calibration and the hand-eye peer), scan (the processes' scans, for the"
                 " stripes per second with the arm moving)");
  app.add_option("--robot-seeds", robot_seeds,
                 "imperfect robots (seeds 1..N) for the direction-dependent error")
      ->check(CLI::Range(0, 1000));
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ephor-bench-stripe: " << e.what() << "\n";
    return 2;
  }
  std::set<std::string> wanted;
  for (size_t start = 0; start <= sections.size();) {
    const size_t comma = std::min(sections.find(',', start), sections.size());
    const std::string name = sections.substr(start, comma - start);
    if (name != "random" && name != "scene" && name != "direction" && name != "scan") {
      std::cerr << "ephor-bench-stripe: --sections: unknown section \"" << name
                << "\" (random, scene, direction, scan)\n";
      return 2;
    }
    wanted.insert(name);
    start = comma + 1;
  }
  if (!out_dir.empty() && !std::filesystem::is_directory(out_dir)) {
    std::cerr << "ephor-bench-stripe: --out-dir " << out_dir << " is not a directory\n";
    return 2;
  }
  try {
    nlohmann::json out;
    if (wanted.count("random")) out["random_error"] = random_error_and_speed(scenes, seed, out_dir);
    if (wanted.count("scene")) out["whole_scene"] = whole_scene(scenes, seed, out_dir);
    if (wanted.count("direction")) {
      nlohmann::json calibration, refined = nlohmann::json::array(),
                                  hand_eye = nlohmann::json::array();
      out["direction_dependent"] =
          direction_dependent(scenes, seed, robot_seeds, calibration, refined, hand_eye);
      out["calibration"] = calibration;
      out["calibration_refined"] = refined;
      out["hand_eye"] = hand_eye;
    }
    if (wanted.count("scan")) out["scanned"] = scanned_speed(scenes, out_dir);
    out["paper_direction_error_mm"] = paper::kDirectionErrorMm;
    out["target_direction_error_mm"] = target::kDirectionErrorMm;
    if (!json_path.empty()) {
      std::FILE* f = std::fopen(json_path.c_str(), "w");
      if (!f) {
        std::cerr << "ephor-bench-stripe: cannot write " << json_path << "\n";
        return 2;
      }
      const std::string text = out.dump(2) + "\n";
      std::fwrite(text.data(), 1, text.size(), f);
      std::fclose(f);
    }
  } catch (const std::exception& e) {
    std::cerr << "ephor-bench-stripe: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
