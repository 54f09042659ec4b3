// ephor-catch-harness: the catching system's perception in simulated time
// (paper 000, sections 3-5.4), deterministic, for measuring the algorithms
// offline without the load of a real-time run: the simulator's pegged board
// and renderer (ephor_catch_sim), then, frame by frame as the live processes
// do it, the circles and IPPE pose at start-up, frame differencing in the
// window of interest around the previous world-model output
// (MotionCentroid, BallWindow), and the world model with the pegs as
// measured (BallWorldModel). Scored against the simulator's truth:
//
//   - position error (mm, B) of the filtered ball and of the raw measurement
//     on every frame with the ball on the board;
//   - per ball, how long before the true exit the predicted exit x settled
//     within --tolerance-mm (every later prediction inside), the monitor's
//     classify_miss rule; the last prediction's error.
//
//   ephor-catch-harness --seed 1 --balls 10 [--verbose]
//
// The arm stands still at the ready point (in view near the bottom edge on
// most seeds); it does not move, so the live run's arm motion in view is not
// reproduced. Frames every 1/60 s of simulated time, physics in 1 ms steps.
// Output: one line per ball and a summary line (JSON with --json).

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "common/catch/board_file.h"
#include "common/catch/board_model.h"
#include "common/catch/sim/board_renderer.h"
#include "common/catch/sim/board_world.h"
#include "common/catch/sim/catch_cell.h"
#include "common/catch/sim/catch_scenario.h"
#include "common/catch/vision/ball_window.h"
#include "common/catch/vision/board_pose_estimator.h"
#include "common/catch/vision/circle_finder.h"
#include "common/catch/vision/motion_centroid.h"
#include "common/catch/worldmodel/ball_world_model.h"
#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/geometry/workcell_file.h"
#include "common/runtime/process_args.h"

namespace {

using namespace ephor;
using namespace ephor::catching;

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(std::floor(p / 100.0 * v.size())));
  return v[i];
}

struct BallScore {
  int ball = 0;
  double true_exit_x_mm = 0.0;
  double exit_time_s = 0.0;      // from release
  double lead_s = std::nan("");  // settled this long before the exit (NaN: never)
  // The same rule for a prediction from the true state (position and
  // velocity) with the pegs the model knows: the ceiling of a perfect filter.
  double oracle_lead_s = std::nan("");
  double last_error_mm = std::nan("");
  double max_error_mm = 0.0;    // filtered position, while on the board
  double max_error_y_mm = 0.0;  // truth y where it was largest
  int frames = 0, tracked = 0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ephor-catch-harness: catching perception in simulated time against the truth"};
  uint64_t seed = 1;
  int balls = 10;
  double tolerance_mm = 30.0, gap_s = 1.0, pixel_sigma_px = 0.5, accel_sigma_y = 200.0,
         bounce_nis = 16.0, peg_sigma_mm = 0.5, restitution_sigma = 0.05, bounce_min_cos = 0.2;
  bool verbose = false, no_pegs = false, known_radius = false, park = false, true_centre = false,
       no_background = false, arm_moves = false, exact_pegs = false;
  std::string json_path, board_path = "deploy/catch/board.pbtxt",
                         workcell_path = "deploy/catch/workcell.pbtxt";
  app.add_option("--seed", seed, "scenario seed (default 1)");
  app.add_option("--balls", balls, "balls, one after another (default 10)")
      ->check(CLI::Range(1, 10000));
  app.add_option("--tolerance-mm", tolerance_mm, "exit x tolerance for 'settled' (default 30)")
      ->check(CLI::Range(1.0, 1000.0));
  app.add_option("--gap-s", gap_s, "frames without a ball between balls, s (default 1)")
      ->check(CLI::Range(0.1, 60.0));
  app.add_flag("--verbose", verbose, "one line per frame");
  app.add_option("--pixel-sigma-px", pixel_sigma_px, "world model's centroid noise (default 0.5)")
      ->check(CLI::Range(0.01, 100.0));
  app.add_option("--accel-sigma-y", accel_sigma_y, "Kalman accel noise down the slope, mm/s^2")
      ->check(CLI::Range(0.0, 100000.0));
  app.add_option("--bounce-nis", bounce_nis, "Kalman bounce NIS threshold (default 16)")
      ->check(CLI::Range(0.0, 1000.0));
  app.add_option("--peg-sigma-mm", peg_sigma_mm,
                 "Kalman: the pegs' survey error for a modelled bounce, mm (default 0.5)")
      ->check(CLI::Range(0.0, 100.0));
  app.add_option("--restitution-sigma", restitution_sigma,
                 "Kalman: the restitution's error for a modelled bounce (default 0.05)")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--bounce-min-cos", bounce_min_cos,
                 "Kalman: floor of cos(angle of incidence) for a modelled bounce (default 0.2)")
      ->check(CLI::Range(0.01, 1.0));
  app.add_flag("--no-pegs", no_pegs, "the world model does not know the pegs");
  app.add_flag("--known-radius", known_radius,
               "give the vision the ball's image radius from the pose (the offline tracker's way)");
  app.add_flag("--true-centre", true_centre,
               "feed the world model the ball centre's true projection (the vision's ceiling)");
  app.add_flag("--no-background", no_background,
               "centre on the crescents only, not on the disc against the reference image");
  app.add_flag("--arm-moves", arm_moves,
               "the arm swings 0.3 rad in view during each roll (as Prim chasing) and back "
               "between balls");
  app.add_flag("--exact-pegs", exact_pegs,
               "the world model knows the pegs exactly (not with the simulator's 0.5 mm noise)");
  app.add_flag("--park", park, "the arm parked out of view instead of at the ready point");
  app.add_option("--board", board_path, "board file (common/catch/board.proto)");
  app.add_option("--workcell", workcell_path, "work cell file");
  app.add_option("--json", json_path, "write the summary and per-ball scores here");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;

  if (!json_path.empty()) {
    // Bad output file: one line, status 2, before any work.
    std::ofstream probe(json_path, std::ios::app);
    if (!probe) {
      std::cerr << "ephor-catch-harness: --json " << json_path << ": cannot write there\n";
      return 2;
    }
  }
  try {
    const BoardSpec board = load_board_file(resolve_repo_path(board_path));
    const geometry::Workcell workcell =
        geometry::load_workcell_file(resolve_repo_path(workcell_path));
    const CatchScenario scenario = CatchScenario::draw(seed, board);
    const CatchCell cell(scenario, workcell);
    BoardRenderer renderer(scenario, CupSpec{}, seed);
    BoardWorld world(scenario);
    const CameraIntrinsics& intrinsics = scenario.intrinsics;
    cv::Mat image;

    // Start-up as ephor-catch-vision: ten frames of the still board, arm parked.
    const ArmView parked = cell.arm_view(cell.park_joints());
    ArmView arm = park ? parked : cell.arm_view(cell.ready_joints());
    std::vector<cv::Mat> init;
    for (int i = 0; i < 10; ++i) {
      renderer.render(std::nullopt, parked, image);
      init.push_back(image.clone());
    }
    const CircleFinderResult circles = CircleFinder(board, intrinsics, {}).find(init);
    if (!circles.found) {
      std::cerr << "ephor-catch-harness: seed " << seed << ": circles not found ("
                << circles.problem << ")\n";
      return 1;
    }
    std::array<Eigen::Vector2d, 4> c;
    for (size_t k = 0; k < 4; ++k) c[k] = circles.circles[k].centroid_px;
    const BoardPoseResult pose = BoardPoseEstimator(board, intrinsics).estimate(c);
    if (!pose.ok) {
      std::cerr << "ephor-catch-harness: seed " << seed << ": pose: " << pose.problem << "\n";
      return 1;
    }

    // Vision and world model as the processes configure them.
    MotionCentroidOptions motion_options;
    if (known_radius) {
      const Eigen::Vector3d centre_c =
          pose.board_to_camera *
          Eigen::Vector3d(board.width_mm / 2.0, board.height_mm / 2.0, board.ball_radius_mm());
      motion_options.ball_radius_px =
          0.5 * (intrinsics.fx + intrinsics.fy) * board.ball_radius_mm() / centre_c.z();
    }
    motion_options.background_centre = !no_background;
    MotionCentroid motion(motion_options);
    const BallWindow window(board, intrinsics, pose.board_to_camera,
                            BallWindowOptions{24.0, 1.0 / 30.0, 0.1});
    BallWorldModelParams params;
    params.acquire_max_y_mm = 150.0;
    params.pixel_sigma_px = pixel_sigma_px;
    params.filter.accel_sigma_y_mm_s2 = accel_sigma_y;
    params.filter.bounce_nis_threshold = bounce_nis;
    params.filter.peg_position_sigma_mm = peg_sigma_mm;
    params.filter.restitution_sigma = restitution_sigma;
    params.filter.bounce_min_cos = bounce_min_cos;
    BallWorldModel model(board, scenario.placement, intrinsics, pose.board_to_camera, params);
    // The oracle: the exit predicted from the true state, with the model's pegs.
    ExitPredictor oracle(board, scenario.placement, params.exit);
    if (!no_pegs) {
      // The pegs as ephor-catch-sim publishes them: 0.5 mm of noise, its seed.
      std::vector<Eigen::Vector2d> pegs = scenario.measured_pegs();
      if (exact_pegs)
        for (size_t i = 0; i < pegs.size(); ++i)
          pegs[i] = Eigen::Vector2d(scenario.pegs[i].x_mm, scenario.pegs[i].y_mm);
      model.set_pegs(pegs, 0.5 * scenario.peg_diameter_mm);
      oracle.set_pegs(pegs, 0.5 * scenario.peg_diameter_mm);
    }

    const double frame_s = 1.0 / 60.0, step_s = 0.001;
    double t = 0.0, next_frame_t = 0.0;
    int64_t frame_index = 0;
    std::vector<double> filtered_errors, measured_errors, pixel_errors;
    std::vector<BallScore> scores;

    // Where the arm is at world time t (none: it stays where it is).
    std::function<ArmView(double)> arm_of_t;

    // One camera frame at world time t: render, vision, world model.
    auto camera_frame = [&](const std::optional<Eigen::Vector3d>& ball_b) -> const BallFrame& {
      if (arm_of_t) arm = arm_of_t(t);
      const std::optional<Eigen::Vector2d> true_px = renderer.render(ball_b, arm, image);
      const int64_t utime = static_cast<int64_t>(std::llround(t * 1e6)) + 1'000'000;
      const BallFrame& previous = model.last();
      std::optional<cv::Rect> w;
      if (model.frames() > 0 && previous.has_state && previous.status == BallStatus::kTracking)
        w = window.around(previous.position_b_mm, previous.velocity_b_mm_s,
                          static_cast<double>(utime - previous.utime) / 1e6);
      const MotionMeasurement m = motion.process(image, w);
      std::optional<Eigen::Vector2d> centroid;
      if (m.found && m.centroid_px.allFinite()) centroid = m.centroid_px;
      if (true_centre) centroid = true_px;
      if (true_px && centroid) pixel_errors.push_back((*centroid - *true_px).norm());
      if (verbose && true_px)
        std::cout << "  px true " << true_px->x() << " " << true_px->y() << " found " << m.found
                  << " bg " << m.from_background << " centre " << m.centroid_px.x() << " "
                  << m.centroid_px.y() << " area " << m.area_px << " sign " << m.contrast_sign
                  << (w ? " window" : " full") << "\n";
      ++frame_index;
      return model.update(utime, centroid);
    };
    auto advance = [&](double until_s, const std::function<void(const BallFrame&)>& on_frame) {
      while (t + 1e-9 < until_s) {
        world.step(step_s);
        t += step_s;
        if (t + 1e-9 >= next_frame_t) {
          next_frame_t += frame_s;
          const BallState s = world.state();
          std::optional<Eigen::Vector3d> ball_b;
          if (s.on_board) ball_b = s.position_b_mm;
          on_frame(camera_frame(ball_b));
        }
      }
    };
    const auto ignore = [](const BallFrame&) {};
    advance(1.0, ignore);  // the motion detector's ring fills

    for (int k = 0; k < balls; ++k) {
      world.release(scenario.release(k));
      const double release_t = t;
      const SimulatedExit truth_exit = world.predict_exit();
      BallScore score;
      score.ball = k;
      if (!truth_exit.exit) {
        std::cout << "ball " << k << ": stalls; skipped\n";
        advance(t + 10.0 + gap_s, ignore);
        continue;
      }
      const BoardExit& ex = *truth_exit.exit;
      score.true_exit_x_mm = ex.x_b_mm;
      score.exit_time_s = ex.time_s - release_t;
      std::optional<double> settled_since;  // world time since all predictions were inside
      std::optional<double> oracle_settled_since;
      bool any_prediction = false;
      if (arm_moves) {
        // As Prim chasing a prediction: from 0.15 s after the release the
        // arm swings 0.3 rad about its base over 0.6 s, in view.
        const double sign = k % 2 == 0 ? 1.0 : -1.0;
        arm_of_t = [&cell, release_t, sign](double now) {
          const double f = std::clamp((now - release_t - 0.15) / 0.6, 0.0, 1.0);
          arm::Joints q = cell.ready_joints();
          q[0] += sign * 0.3 * f;
          return cell.arm_view(q);
        };
      }
      advance(ex.time_s + 0.3, [&](const BallFrame& f) {
        const BallState s = world.state();
        if (!s.on_board) return;
        ++score.frames;
        const Eigen::Vector2d truth = s.position_b_mm.head<2>();
        {
          Eigen::Vector4d state;
          state << truth, s.velocity_b_mm_s.head<2>();
          const ExitPrediction o = oracle.predict(state, Eigen::Matrix4d::Zero());
          if (!o.ok() || std::abs(o.exit_x_b_mm - ex.x_b_mm) > tolerance_mm)
            oracle_settled_since.reset();
          else if (!oracle_settled_since)
            oracle_settled_since = t;
        }
        if (f.has_measurement)
          measured_errors.push_back((f.measured_b_mm.head<2>() - truth).norm());
        if (f.has_state &&
            (f.status == BallStatus::kTracking || f.status == BallStatus::kRejected)) {
          ++score.tracked;
          const double e = (f.position_b_mm - truth).norm();
          filtered_errors.push_back(e);
          if (e > score.max_error_mm) {
            score.max_error_mm = e;
            score.max_error_y_mm = truth.y();
          }
        }
        if (f.has_prediction && f.status != BallStatus::kExited) {
          any_prediction = true;
          const double err = std::abs(f.exit.exit_x_b_mm - ex.x_b_mm);
          score.last_error_mm = err;
          if (err > tolerance_mm)
            settled_since.reset();
          else if (!settled_since)
            settled_since = t;
        }
        if (verbose)
          std::cout << "  t " << t - release_t << " truth " << truth.x() << " " << truth.y()
                    << " v " << s.velocity_b_mm_s.x() << " " << s.velocity_b_mm_s.y() << " | "
                    << to_string(f.status) << " " << to_string(f.reason)
                    << (f.has_measurement ? " meas " + std::to_string(f.measured_b_mm.x()) + " " +
                                                std::to_string(f.measured_b_mm.y())
                                          : std::string(" no meas"))
                    << (f.has_state ? " est " + std::to_string(f.position_b_mm.x()) + " " +
                                          std::to_string(f.position_b_mm.y()) + " v " +
                                          std::to_string(f.velocity_b_mm_s.x()) + " " +
                                          std::to_string(f.velocity_b_mm_s.y())
                                    : std::string())
                    << (f.has_prediction ? " exit " + std::to_string(f.exit.exit_x_b_mm) : "")
                    << (f.bounce ? " BOUNCE" : "") << "\n";
      });
      if (any_prediction && settled_since) score.lead_s = ex.time_s - *settled_since;
      if (oracle_settled_since) score.oracle_lead_s = ex.time_s - *oracle_settled_since;
      std::cout << "ball " << k << ": exit x " << score.true_exit_x_mm << " mm after "
                << score.exit_time_s << " s; settled " << score.lead_s << " s ahead (oracle "
                << score.oracle_lead_s << " s); last error " << score.last_error_mm
                << " mm; max track error " << score.max_error_mm << " mm at y "
                << score.max_error_y_mm << "; tracked " << score.tracked << "/" << score.frames
                << "\n";
      scores.push_back(score);
      if (arm_moves) {
        // The arm comes back from a catch beside the board to the ready
        // point through the camera's view in the first 0.6 s of the gap.
        const double gap_start = t;
        arm::Joints away = cell.ready_joints();
        away[0] += (k % 2 == 0 ? 0.3 : -0.3);
        arm_of_t = [&cell, gap_start, away](double now) {
          const double f = std::clamp((now - gap_start) / 0.6, 0.0, 1.0);
          return cell.arm_view(away + f * (cell.ready_joints() - away));
        };
        advance(t + gap_s, ignore);
        arm_of_t = nullptr;
        arm = cell.arm_view(cell.ready_joints());
      } else {
        advance(t + gap_s, ignore);
      }
    }

    int lead05 = 0, lead06 = 0, lead07 = 0, wrong = 0, oracle05 = 0, oracle07 = 0;
    for (const auto& s : scores) {
      if (std::isfinite(s.oracle_lead_s) && s.oracle_lead_s >= 0.5) ++oracle05;
      if (std::isfinite(s.oracle_lead_s) && s.oracle_lead_s >= 0.7) ++oracle07;
      if (std::isfinite(s.lead_s) && s.lead_s >= 0.5) ++lead05;
      if (std::isfinite(s.lead_s) && s.lead_s >= 0.6) ++lead06;
      if (std::isfinite(s.lead_s) && s.lead_s >= 0.7) ++lead07;
      if (!(s.last_error_mm <= tolerance_mm)) ++wrong;
    }
    nlohmann::json j;
    j["seed"] = seed;
    j["balls"] = scores.size();
    j["settled_0_5s"] = lead05;
    j["settled_0_6s"] = lead06;
    j["settled_0_7s"] = lead07;
    j["wrong_place"] = wrong;
    j["oracle_settled_0_5s"] = oracle05;
    j["oracle_settled_0_7s"] = oracle07;
    j["position_error_mm"] = {{"p50", percentile(filtered_errors, 50)},
                              {"p99", percentile(filtered_errors, 99)},
                              {"max", percentile(filtered_errors, 100)},
                              {"n", filtered_errors.size()}};
    j["measurement_error_mm"] = {{"p50", percentile(measured_errors, 50)},
                                 {"p99", percentile(measured_errors, 99)},
                                 {"max", percentile(measured_errors, 100)},
                                 {"n", measured_errors.size()}};
    j["pixel_error_px"] = {{"p50", percentile(pixel_errors, 50)},
                           {"p99", percentile(pixel_errors, 99)},
                           {"n", pixel_errors.size()}};
    std::cout << j.dump() << "\n";
    if (!json_path.empty()) {
      nlohmann::json per_ball = nlohmann::json::array();
      for (const auto& s : scores)
        per_ball.push_back(
            {{"ball", s.ball},
             {"exit_x_mm", s.true_exit_x_mm},
             {"lead_s", std::isfinite(s.lead_s) ? nlohmann::json(s.lead_s) : nlohmann::json()},
             {"last_error_mm",
              std::isfinite(s.last_error_mm) ? nlohmann::json(s.last_error_mm) : nlohmann::json()},
             {"max_error_mm", s.max_error_mm}});
      j["per_ball"] = per_ball;
      std::ofstream(json_path) << j.dump(1) << "\n";
    }
  } catch (const ephor::ConfigError& e) {
    std::cerr << "ephor-catch-harness: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ephor-catch-harness: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
