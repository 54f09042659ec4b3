// ephor-bench-rambo: figures of the RAMBO core (common/rambo) beside the
// paper's (seed 001), in one run:
//   ordering    for 2..8 tasks on a tumbling target: reaching trajectories
//               computed by greedy, exhaustive and DP, the total time of the
//               order each finds, and whether DP's order is exhaustive's.
//               The cost of a move is the intercept time of a straight line at
//               a safe tool speed (the paper's section 9 serial-machine rule)
//               onto the goal point's true trajectory: time-dependent, cheap
//               enough for 8! orders. The joint-space ReachingPlanner's cost
//               per reaching trajectory is measured apart (reaching section).
//   prediction  goal-point error 0.5, 1 and 2 s ahead of a torque-free
//               tumbling target observed at 30 Hz for 2 s (0.5 mm, 0.2 deg
//               noise): quadratic and linear fits (the paper) and the
//               rigid-body model.
//   pose        time per pose and error: triangle pairs (exact perspective,
//               paraperspective; with and without pruning by a prior) and
//               OpenCV's solvePnPRansac (AP3P) over every image point x model
//               vertex correspondence, on the same image triples (0.5 px noise).
//
//   reach       for the live runs' targets (the model file, seeds 1..N,
//               free tumble and RM-501), how much of a 120 s run each
//               diode's goal pose is within the PUMA's reach at landing and
//               a hold later (GoalReachSurvey): a diode never in reach cannot
//               be tagged by any order or timing.
//   live-prediction  the same targets (free and RM-501) seen at 5 Hz with the
//               live pose error: every goal point predicted 0.5, 1, 2 s ahead
//               by the rigid body and the paper's polynomial fits.
//
//   ephor-bench-rambo [--json FILE] [--seed S] [--poses N] [--seeds N]
//                     [--sections ordering,reaching,prediction,pose,live-prediction,reach]
//                     [--model FILE] [--reach-seeds N]

#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/calib3d.hpp>

#include "common/rambo/goal_reach_survey.h"
#include "common/rambo/polynomial_pose_predictor.h"
#include "common/rambo/ransac_pose_peer.h"
#include "common/rambo/reaching_planner.h"
#include "common/rambo/rigid_body_pose_predictor.h"
#include "common/rambo/rm501_carrier.h"
#include "common/rambo/target_model_file.h"
#include "common/rambo/task_orderer.h"
#include "common/rambo/triangle_pose_estimator.h"
#include "common/rambo/tumbling_body.h"

namespace {

using namespace ephor::rambo;
// CPU time of this thread: the machine runs other real-time work, and
// wall-clock times there measure its load, not this code.
struct Clock {
  using time_point = double;  // ms
  static double now() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
  }
};

double ms_since(double t0_ms) { return Clock::now() - t0_ms; }

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const auto k =
      std::min(v.size() - 1, static_cast<std::size_t>(p / 100.0 * static_cast<double>(v.size())));
  return v[k];
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? std::nan("") : s / static_cast<double>(v.size());
}

const Eigen::Vector3d kMoments(1.0, 2.0, 3.0);  // truncated box-like inertia ratios

TargetModel bench_model() {
  return TargetModel::truncated_box(140, 100, 70, Eigen::Vector3d(40, 30, 25));
}

TumblingBody random_tumbler(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Isometry3d p0 = Eigen::Isometry3d::Identity();
  p0.translation() << 550.0 + 50 * u(rng), 100 * u(rng), 250.0 + 50 * u(rng);
  p0.linear() = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
  p0.linear() =
      Eigen::AngleAxisd(3.0 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng) + 2.0).normalized())
          .toRotationMatrix();
  // Spin mostly about the intermediate axis: a tumble, not a constant twist.
  const Eigen::Vector3d w(0.2 * u(rng), 0.8 + 0.3 * u(rng), 0.2 * u(rng));
  return TumblingBody(p0, Eigen::Vector3d(20 * u(rng), 20 * u(rng), 10 * u(rng)), w, kMoments);
}

// Diodes' goal points: 150 mm out along face normals (faces in turn, a
// second diode on a face shifted 20 mm).
std::vector<Eigen::Vector3d> goal_points(const TargetModel& m, int n) {
  std::vector<Eigen::Vector3d> g;
  for (int i = 0; i < n; ++i) {
    const int f = i % static_cast<int>(m.faces().size());
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int v : m.faces()[static_cast<std::size_t>(f)])
      c += m.vertices()[static_cast<std::size_t>(v)];
    c /= static_cast<double>(m.faces()[static_cast<std::size_t>(f)].size());
    const Eigen::Vector3d nrm = m.face_normal(f);
    const Eigen::Vector3d side = nrm.unitOrthogonal();
    g.push_back(c + 150.0 * nrm + (i >= 7 ? 20.0 : 0.0) * side);
  }
  return g;
}

nlohmann::json bench_ordering(int seeds, unsigned seed0) {
  nlohmann::json out = nlohmann::json::array();
  const TargetModel model = bench_model();
  const double speed = 250.0;  // mm/s, a safe fraction of the tool's top speed
  std::printf("ordering (intercept at %.0f mm/s, hold 0.5 s per task, %d seeds)\n", speed, seeds);
  std::printf(
      "  n  greedy  exhaust      dp  paper-dp  formula(g/e/dp)      total s g/e/dp     dp==ex\n");
  for (int n = 2; n <= 8; ++n) {
    std::vector<double> tg, te, td;
    long cg = 0, ce = 0, cd = 0;
    int equal = 0;
    double ms_e = 0, ms_d = 0;
    for (int s = 0; s < seeds; ++s) {
      std::mt19937 rng(seed0 + 1000u * static_cast<unsigned>(n) + static_cast<unsigned>(s));
      TumblingBody body = random_tumbler(rng);
      const auto goals = goal_points(model, n);
      // Goal positions on a 10 ms grid over 60 s (the tumble is cheap to sample once).
      const double dt = 0.01;
      const int steps = 6001;
      std::vector<std::vector<Eigen::Vector3d>> path(static_cast<std::size_t>(n));
      for (int k = 0; k < steps; ++k) {
        const Eigen::Isometry3d p = body.pose(k * dt);
        for (int i = 0; i < n; ++i)
          path[static_cast<std::size_t>(i)].push_back(p * goals[static_cast<std::size_t>(i)]);
      }
      const Eigen::Vector3d tool0(300.0, -300.0, 400.0);
      auto at = [&](int i, double t) {
        const double u = std::clamp(t / dt, 0.0, steps - 1.0001);
        const auto k = static_cast<std::size_t>(u);
        const double f = u - static_cast<double>(k);
        const auto& v = path[static_cast<std::size_t>(i)];
        return ((1 - f) * v[k] + f * v[k + 1]).eval();
      };
      auto duration = [&](int from, int to, double t0) {
        const Eigen::Vector3d start = from < 0 ? tool0 : at(from, t0);
        double T = (at(to, t0) - start).norm() / speed;
        for (int it = 0; it < 30; ++it)
          T = (at(to, t0 + T) - start).norm() / speed;  // intercept fixed point
        return 0.2 + T;                                 // + settling
      };
      TaskOrderer o(std::vector<double>(static_cast<std::size_t>(n), 0.5), duration);
      const TaskOrder g = o.greedy(0.0);
      auto t1 = Clock::now();
      const TaskOrder e = o.exhaustive(0.0);
      ms_e += ms_since(t1);
      t1 = Clock::now();
      const TaskOrder d = o.dynamic_programming(0.0);
      ms_d += ms_since(t1);
      tg.push_back(g.total_time_s), te.push_back(e.total_time_s), td.push_back(d.total_time_s);
      cg = g.reaching_trajectories, ce = e.reaching_trajectories, cd = d.reaching_trajectories;
      if (d.order == e.order && std::abs(d.total_time_s - e.total_time_s) < 1e-9) ++equal;
    }
    std::printf("  %d  %6ld  %7ld  %6ld  %8ld  %4ld/%6ld/%5ld    %5.2f/%5.2f/%5.2f     %d/%d\n", n,
                cg, ce, cd, static_cast<long>(TaskOrderer::paper_dp_count(n)),
                static_cast<long>(TaskOrderer::greedy_count(n)),
                static_cast<long>(TaskOrderer::exhaustive_count(n)),
                static_cast<long>(TaskOrderer::dp_count(n)), mean(tg), mean(te), mean(td), equal,
                seeds);
    out.push_back(
        {{"tasks", n},
         {"trajectories", {{"greedy", cg}, {"exhaustive", ce}, {"dp", cd}}},
         {"formula",
          {{"greedy", TaskOrderer::greedy_count(n)},
           {"exhaustive", TaskOrderer::exhaustive_count(n)},
           {"dp", TaskOrderer::dp_count(n)},
           {"paper_exhaustive", TaskOrderer::paper_exhaustive_count(n)},
           {"paper_dp_states", TaskOrderer::paper_dp_count(n)}}},
         {"total_time_s_mean", {{"greedy", mean(tg)}, {"exhaustive", mean(te)}, {"dp", mean(td)}}},
         {"greedy_excess_s_max",
          [&] {
            double m = 0;
            for (std::size_t i = 0; i < tg.size(); ++i) m = std::max(m, tg[i] - te[i]);
            return m;
          }()},
         {"cpu_ms_mean", {{"exhaustive", ms_e / seeds}, {"dp", ms_d / seeds}}},
         {"dp_equals_exhaustive", equal},
         {"seeds", seeds}});
  }
  return out;
}

nlohmann::json bench_reaching() {
  // The joint-space planner on the PUMA 560: a goal moving with a tumbling
  // target, from rest; time per planned reach (durations scanned), both methods.
  const ephor::arm::Puma560 arm(100.0);
  nlohmann::json out;
  // The goal point: fixed in the target frame 180 mm out along its z axis,
  // the tool's z (the laser) pointing back at the centre.
  Eigen::Isometry3d goal_in_target = Eigen::Isometry3d::Identity();
  goal_in_target.translation() << 0.0, 0.0, 180.0;
  goal_in_target.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  // A slow tumble (0.15 rad/s) below the tool: at t = 0 the goal is 500 mm
  // out at 29 deg of waist, the laser pointing down at the target; the tool
  // starts at rest 52 deg of waist away, pointing the same way.
  auto outward_tool = [](double waist_rad) {
    const Eigen::Vector3d x(std::cos(waist_rad), std::sin(waist_rad), 0.0);
    const Eigen::Vector3d z(0.0, 0.0, -1.0);  // laser pointing down at the target
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() << x, z.cross(x), z;
    t.translation() = 500.0 * x + Eigen::Vector3d(0.0, 0.0, -200.0);
    return t;
  };
  const Eigen::Isometry3d p0 = outward_tool(0.5) * goal_in_target.inverse();
  TumblingBody body(p0, Eigen::Vector3d(5.0, 5.0, 0.0), Eigen::Vector3d(0.02, 0.15, 0.02),
                    kMoments);
  const auto q0_opt = arm.nearest_inverse(outward_tool(-0.4), Joints::Zero());
  if (!q0_opt) return {{"error", "start pose out of reach"}};
  const Joints q0 = *q0_opt;
  auto cur = std::make_shared<const SampledJointTrajectory>(
      SampledJointTrajectory::from_function(0.0, 0.01, 1001, [&](double) {
        return JointSample{q0, Joints::Zero(), Joints::Zero()};
      }));
  auto goal_pose = [&](double t) { return Eigen::Isometry3d(body.pose(t) * goal_in_target); };
  TargetSphere sphere{[&](double t) -> Eigen::Vector3d { return body.pose(t).translation(); },
                      bench_model().bounding_radius_mm()};
  for (auto m : {ReachingMethod::kCubicSpline, ReachingMethod::kBlend}) {
    ReachingOptions o;
    o.method = m;
    ReachingPlanner p(arm, o);
    const auto t1 = Clock::now();
    const ReachingPlan plan = p.plan(cur, goal_pose, 0.0, 8.0, &sphere, 0.5);
    if (!plan.feasible())
      std::printf("  (%s; refused at t = %.2f s, value %.3f)\n", plan.reason.c_str(),
                  plan.last_refusal.t_s, plan.last_refusal.value);
    const double ms = ms_since(t1);
    std::printf("reaching %-5s: %s, T = %.2f s, %d durations tried, %.1f ms\n", to_string(m),
                to_string(plan.status), plan.feasible() ? plan.duration_s() : -1.0,
                plan.durations_tried, ms);
    out[to_string(m)] = {{"status", to_string(plan.status)},
                         {"duration_s", plan.feasible() ? plan.duration_s() : -1.0},
                         {"durations_tried", plan.durations_tried},
                         {"plan_ms", ms}};
  }
  return out;
}

nlohmann::json bench_prediction(int seeds, unsigned seed0) {
  const std::vector<double> horizons{0.5, 1.0, 2.0};
  std::vector<std::vector<double>> err_q(3), err_l(3), err_r(3), err_v(3);
  const Eigen::Isometry3d goal(Eigen::Translation3d(0, 0, 180.0));
  double fit_ms_r = 0, fit_ms_q = 0;
  for (int s = 0; s < seeds; ++s) {
    std::mt19937 rng(seed0 + static_cast<unsigned>(s));
    TumblingBody body = random_tumbler(rng);
    std::normal_distribution<double> n(0.0, 1.0);
    std::vector<PoseSample> obs;
    for (int k = 0; k <= 60; ++k) {
      const double t = k / 30.0;
      PoseSample x{t, body.pose(t)};
      x.pose.translation() += 0.5 * Eigen::Vector3d(n(rng), n(rng), n(rng));
      const Eigen::Vector3d e = (0.2 * M_PI / 180.0) * Eigen::Vector3d(n(rng), n(rng), n(rng));
      x.pose.linear() =
          x.pose.linear() * Eigen::AngleAxisd(e.norm(), e.normalized()).toRotationMatrix();
      obs.push_back(x);
    }
    PolynomialPosePredictor quad(2), lin(1), vec(2, RotationCoordinates::kRotationVector);
    RigidBodyPosePredictor rigid(kMoments);
    auto t1 = Clock::now();
    if (!quad.fit(obs, nullptr)) continue;
    fit_ms_q += ms_since(t1);
    if (!lin.fit(obs, nullptr) || !vec.fit(obs, nullptr)) continue;
    t1 = Clock::now();
    if (!rigid.fit(obs, nullptr)) continue;
    fit_ms_r += ms_since(t1);
    for (std::size_t h = 0; h < horizons.size(); ++h) {
      const double t = obs.back().t_s + horizons[h];
      const Eigen::Vector3d truth = (body.pose(t) * goal).translation();
      err_q[h].push_back((quad.predict_goal(goal, t).pose.translation() - truth).norm());
      err_l[h].push_back((lin.predict_goal(goal, t).pose.translation() - truth).norm());
      err_v[h].push_back((vec.predict_goal(goal, t).pose.translation() - truth).norm());
      err_r[h].push_back((rigid.predict_goal(goal, t).pose.translation() - truth).norm());
    }
  }
  nlohmann::json out = nlohmann::json::array();
  std::printf(
      "prediction: goal point 180 mm from the centre, %d tumbling targets, error mm (p50 / p90)\n",
      seeds);
  for (std::size_t h = 0; h < horizons.size(); ++h) {
    std::printf(
        "  %.1f s: quadratic %6.1f / %6.1f  linear %6.1f / %6.1f  quadratic rot-vector %6.1f / "
        "%6.1f  rigid body %5.2f / %5.2f\n",
        horizons[h], percentile(err_q[h], 50), percentile(err_q[h], 90), percentile(err_l[h], 50),
        percentile(err_l[h], 90), percentile(err_v[h], 50), percentile(err_v[h], 90),
        percentile(err_r[h], 50), percentile(err_r[h], 90));
    out.push_back(
        {{"horizon_s", horizons[h]},
         {"quadratic_mm", {{"p50", percentile(err_q[h], 50)}, {"p90", percentile(err_q[h], 90)}}},
         {"linear_mm", {{"p50", percentile(err_l[h], 50)}, {"p90", percentile(err_l[h], 90)}}},
         {"quadratic_rotation_vector_mm",
          {{"p50", percentile(err_v[h], 50)}, {"p90", percentile(err_v[h], 90)}}},
         {"rigid_body_mm",
          {{"p50", percentile(err_r[h], 50)}, {"p90", percentile(err_r[h], 90)}}}});
  }
  std::printf("  fit time: quadratic %.3f ms, rigid body %.2f ms\n", fit_ms_q / seeds,
              fit_ms_r / seeds);
  return {{"horizons", out},
          {"fit_ms", {{"quadratic", fit_ms_q / seeds}, {"rigid_body", fit_ms_r / seeds}}},
          {"targets", seeds}};
}

// The live runs' two target motions (the sim's free tumble at 2 deg/s and
// the RM-501 carrying it, seeds 1..N, model file's goal points) observed as
// the live pose process sees them: 5 Hz, 0.8 mm and 0.3 deg noise (its p50
// errors), a window of poses ending every 10 s from 10 to 110 s. Each motion
// model predicts every goal point 0.5, 1, 2, 4 and 8 s past the window's
// last pose (4 and 8 s: how long a prediction may stand in for poses while
// the camera looks past the target).
nlohmann::json bench_live_prediction(const std::string& model_path, int seeds) {
  const RamboCell cell = cell_from_flags(model_path, 0);
  const std::vector<double> horizons{0.5, 1.0, 2.0, 4.0, 8.0};
  struct Model {
    std::string name;
    int degree;  // -1 = rigid body
    RotationCoordinates rotation;
    double window_s;
  };
  const std::vector<Model> models{
      {"rigid body, 1 s (a first fit)", -1, RotationCoordinates::kRotationVector, 1.0},
      {"rigid body, 2 s", -1, RotationCoordinates::kRotationVector, 2.0},
      {"rigid body, 4 s", -1, RotationCoordinates::kRotationVector, 4.0},
      {"quadratic ZYX (paper), 4 s", 2, RotationCoordinates::kZyxAngles, 4.0},
      {"linear rot-vector, 2 s", 1, RotationCoordinates::kRotationVector, 2.0},
      {"linear rot-vector, 4 s", 1, RotationCoordinates::kRotationVector, 4.0},
      {"quadratic rot-vector, 3 s", 2, RotationCoordinates::kRotationVector, 3.0},
      {"quadratic rot-vector, 4 s", 2, RotationCoordinates::kRotationVector, 4.0},
      {"quadratic rot-vector, 6 s", 2, RotationCoordinates::kRotationVector, 6.0},
      {"cubic rot-vector, 6 s", 3, RotationCoordinates::kRotationVector, 6.0},
      {"cubic rot-vector, 8 s", 3, RotationCoordinates::kRotationVector, 8.0}};
  nlohmann::json out;
  std::printf(
      "prediction, the live targets: %d seeds, poses at 5 Hz with 0.8 mm / 0.3 deg noise, every "
      "goal point, error mm p50 / p90\n",
      seeds);
  for (const std::string carrier : {"free", "rm501"}) {
    std::vector<std::vector<std::vector<double>>> err(
        models.size(), std::vector<std::vector<double>>(horizons.size()));
    for (int seed = 1; seed <= seeds; ++seed) {
      const TumblingMotion m = cell.draw_motion(static_cast<std::uint64_t>(seed), 2.0, 1.0);
      std::function<Eigen::Isometry3d(double)> truth;
      std::shared_ptr<TumblingBody> body;
      std::shared_ptr<Rm501Carrier> arm;
      if (carrier == "free") {
        body = std::make_shared<TumblingBody>(m.pose0, m.velocity_mm_s, m.body_rates_rad_s,
                                              cell.principal_moments);
        truth = [body](double t) { return body->pose(t); };
      } else {
        arm = std::make_shared<Rm501Carrier>(m.pose0, static_cast<std::uint64_t>(seed), 1.0);
        truth = [arm](double t) { return arm->pose(t); };
      }
      std::mt19937 rng(static_cast<unsigned>(seed) * 7919u + 17u);
      std::normal_distribution<double> n(0.0, 1.0);
      // Every observation of the run, drawn once, in time order (the body is
      // cheapest queried forward): 5 Hz from 0 to 120 s.
      std::vector<PoseSample> all;
      for (int k = 0; k <= 600; ++k) {
        const double t = 0.2 * k;
        PoseSample x{t, truth(t)};
        x.pose.translation() += (0.8 / std::sqrt(3.0)) * Eigen::Vector3d(n(rng), n(rng), n(rng));
        const Eigen::Vector3d e =
            (0.3 / std::sqrt(3.0) * M_PI / 180.0) * Eigen::Vector3d(n(rng), n(rng), n(rng));
        x.pose.linear() =
            x.pose.linear() * Eigen::AngleAxisd(e.norm(), e.normalized()).toRotationMatrix();
        all.push_back(x);
      }
      for (double t_end = 10.0; t_end <= 110.0; t_end += 10.0) {
        std::vector<std::vector<Eigen::Vector3d>> goal_truth(horizons.size());
        for (std::size_t h = 0; h < horizons.size(); ++h)
          for (int i = 0; i < static_cast<int>(cell.diodes.size()); ++i)
            goal_truth[h].push_back(
                (truth(t_end + horizons[h]) * cell.goal_in_target(i)).translation());
        for (std::size_t k = 0; k < models.size(); ++k) {
          std::vector<PoseSample> window;
          for (const PoseSample& x : all)
            if (x.t_s > t_end - models[k].window_s - 1e-9 && x.t_s <= t_end + 1e-9)
              window.push_back(x);
          std::unique_ptr<PosePredictor> p;
          if (models[k].degree < 0)
            p = std::make_unique<RigidBodyPosePredictor>(cell.principal_moments);
          else
            p = std::make_unique<PolynomialPosePredictor>(models[k].degree, models[k].rotation);
          if (!p->fit(window, nullptr)) continue;
          for (std::size_t h = 0; h < horizons.size(); ++h)
            for (int i = 0; i < static_cast<int>(cell.diodes.size()); ++i)
              err[k][h].push_back(
                  (p->predict_goal(cell.goal_in_target(i), t_end + horizons[h]).pose.translation() -
                   goal_truth[h][static_cast<std::size_t>(i)])
                      .norm());
        }
      }
    }
    std::printf(
        "  %s:%*s   0.5 s            1 s              2 s              4 s              8 s\n",
        carrier.c_str(), static_cast<int>(30 - carrier.size()), "");
    nlohmann::json c;
    for (std::size_t k = 0; k < models.size(); ++k) {
      std::printf("    %-30s", models[k].name.c_str());
      nlohmann::json row;
      for (std::size_t h = 0; h < horizons.size(); ++h) {
        std::printf("  %6.2f / %6.2f", percentile(err[k][h], 50), percentile(err[k][h], 90));
        row[std::to_string(horizons[h]).substr(0, 3) + "s"] = {{"p50", percentile(err[k][h], 50)},
                                                               {"p90", percentile(err[k][h], 90)}};
      }
      std::printf("\n");
      c[models[k].name] = row;
    }
    out[carrier] = c;
  }
  return out;
}

// OpenCV's RANSAC over all correspondence hypotheses (RansacPosePeer: the
// same peer ephor-rambo-pose runs in a live run with --peer-every).
bool ransac_peer(const TargetModel& m, const CameraIntrinsics& cam,
                 const std::vector<ImageTriple>& triples, Eigen::Isometry3d* pose) {
  const auto r = RansacPosePeer(m, cam).estimate(triples);
  if (r) *pose = r->target_in_camera;
  return r.has_value();
}

nlohmann::json bench_pose(int poses, unsigned seed0) {
  const TargetModel model = bench_model();
  const CameraIntrinsics cam;
  std::mt19937 rng(seed0);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  struct Variant {
    std::string name;
    TrianglePoseOptions o;
    bool prior;
    bool peer;
    std::vector<double> ms, mm, deg, tried;
    int found = 0;
  };
  TrianglePoseOptions para;
  para.method = TrianglePoseMethod::kParaperspective;
  para.cluster_radius_mm = 60.0;
  para.cluster_rotation_rad = 0.35;
  para.refine_gate_px = 30.0;
  std::vector<Variant> vs{
      {"triangles_exact", {}, false, false, {}, {}, {}, {}, 0},
      {"triangles_exact_pruned", {}, true, false, {}, {}, {}, {}, 0},
      {"triangles_paraperspective", para, false, false, {}, {}, {}, {}, 0},
      {"triangles_paraperspective_pruned", para, true, false, {}, {}, {}, {}, 0},
      {"opencv_solvePnPRansac_ap3p", {}, false, true, {}, {}, {}, {}, 0}};
  int triples_total = 0;
  for (int i = 0; i < poses; ++i) {
    // The cut corner (the model's only asymmetry) towards the camera, tilted and rolled.
    Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
    const Eigen::Vector3d view(0.4 * u(rng), 0.4 * u(rng), -1.0);
    truth.linear() = (Eigen::AngleAxisd(M_PI * u(rng), Eigen::Vector3d::UnitZ()) *
                      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d(1, 1, 1).normalized(),
                                                         view.normalized()))
                         .toRotationMatrix();
    truth.translation() << 60 * u(rng), 40 * u(rng), 650 + 150 * u(rng);
    const auto triples = synthetic_image_triples(model, cam, truth, 0.5, &rng);
    triples_total += static_cast<int>(triples.size());
    Eigen::Isometry3d prior = truth;  // last estimate: 10 mm and 2 deg off
    prior.translation() += Eigen::Vector3d(6, -5, 6);
    prior.linear() =
        prior.linear() *
        Eigen::AngleAxisd(2 * M_PI / 180, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
    for (auto& v : vs) {
      Eigen::Isometry3d est;
      bool ok = false;
      const auto t1 = Clock::now();
      long tried = 0;
      if (v.peer) {
        ok = ransac_peer(model, cam, triples, &est);
      } else {
        const TrianglePoseEstimator e(model, cam, v.o);
        const TrianglePoseResult r = e.estimate(triples, v.prior ? &prior : nullptr);
        ok = r.found, est = r.target_in_camera, tried = r.matches_tried;
      }
      v.ms.push_back(ms_since(t1));
      v.tried.push_back(static_cast<double>(tried));
      if (!ok) continue;
      ++v.found;
      v.mm.push_back((est.translation() - truth.translation()).norm());
      v.deg.push_back(Eigen::AngleAxisd(est.linear().transpose() * truth.linear()).angle() * 180 /
                      M_PI);
    }
  }
  nlohmann::json out;
  std::printf("pose: %d poses at 500-800 mm, 0.5 px noise, %.1f image triples per image\n", poses,
              static_cast<double>(triples_total) / poses);
  std::printf("  %-34s found   ms p50/p99      mm p50/p99      deg p50/p99   matches\n", "method");
  for (const auto& v : vs) {
    std::printf("  %-34s %3d/%d  %6.2f/%6.2f  %6.2f/%7.2f  %5.2f/%6.2f  %6.0f\n", v.name.c_str(),
                v.found, poses, percentile(v.ms, 50), percentile(v.ms, 99), percentile(v.mm, 50),
                percentile(v.mm, 99), percentile(v.deg, 50), percentile(v.deg, 99), mean(v.tried));
    out[v.name] = {{"found", v.found},
                   {"poses", poses},
                   {"ms", {{"p50", percentile(v.ms, 50)}, {"p99", percentile(v.ms, 99)}}},
                   {"error_mm", {{"p50", percentile(v.mm, 50)}, {"p99", percentile(v.mm, 99)}}},
                   {"error_deg", {{"p50", percentile(v.deg, 50)}, {"p99", percentile(v.deg, 99)}}},
                   {"matches_tried_mean", mean(v.tried)}};
  }
  return out;
}

// The live runs' target (the sim's: RamboCell::draw_motion at 2 deg/s and
// 1 mm/s drift, or the RM-501 from the same start pose) over 120 s.
nlohmann::json bench_reach(const std::string& model_path, int seeds) {
  const RamboCell cell = cell_from_flags(model_path, 0);
  nlohmann::json out;
  std::printf("reach: %s, %d seeds, 120 s at 0.5 s: goal reachable at t and t + 2 s\n",
              model_path.empty() ? "built-in target" : model_path.c_str(), seeds);
  for (const std::string carrier : {"free", "rm501"}) {
    std::vector<std::vector<double>> fraction(cell.diodes.size()), window(cell.diodes.size()),
        from_start(cell.diodes.size());
    std::vector<std::vector<int>> never(cell.diodes.size()), out_at_start(cell.diodes.size());
    for (int seed = 1; seed <= seeds; ++seed) {
      const TumblingMotion m = cell.draw_motion(static_cast<std::uint64_t>(seed), 2.0, 1.0);
      std::vector<DiodeReach> r;
      if (carrier == "free") {
        TumblingBody body(m.pose0, m.velocity_mm_s, m.body_rates_rad_s, cell.principal_moments);
        r = survey_goal_reach(cell, [&](double t) { return body.pose(t); });
      } else {
        const Rm501Carrier arm(m.pose0, static_cast<std::uint64_t>(seed), 1.0);
        r = survey_goal_reach(cell, [&](double t) { return arm.pose(t); });
      }
      for (std::size_t i = 0; i < r.size(); ++i) {
        fraction[i].push_back(r[i].reachable_fraction());
        window[i].push_back(r[i].longest_window_s);
        from_start[i].push_back(r[i].in_reach_from_start_s);
        if (r[i].reachable == 0) never[i].push_back(seed);
        if (r[i].in_reach_from_start_s == 0.0) out_at_start[i].push_back(seed);
      }
    }
    std::printf(
        "  %s: diode        reachable %% of the run: min / p50   longest window s: min / p50"
        "   in reach from the start s: min / p50   out of reach at the start (seeds)   never in "
        "reach (seeds)\n",
        carrier.c_str());
    nlohmann::json c;
    for (std::size_t i = 0; i < cell.diodes.size(); ++i) {
      std::string nv, os;
      for (int sd : never[i]) nv += (nv.empty() ? "" : ",") + std::to_string(sd);
      for (int sd : out_at_start[i]) os += (os.empty() ? "" : ",") + std::to_string(sd);
      std::printf("    %-12s %5.0f / %5.0f   %6.1f / %6.1f   %6.1f / %6.1f   %s   %s\n",
                  cell.diodes[i].name.c_str(), 100.0 * percentile(fraction[i], 0),
                  100.0 * percentile(fraction[i], 50), percentile(window[i], 0),
                  percentile(window[i], 50), percentile(from_start[i], 0),
                  percentile(from_start[i], 50), os.empty() ? "-" : os.c_str(),
                  nv.empty() ? "-" : nv.c_str());
      c[cell.diodes[i].name] = {
          {"reachable_fraction",
           {{"min", percentile(fraction[i], 0)}, {"p50", percentile(fraction[i], 50)}}},
          {"longest_window_s",
           {{"min", percentile(window[i], 0)}, {"p50", percentile(window[i], 50)}}},
          {"in_reach_from_start_s",
           {{"min", percentile(from_start[i], 0)}, {"p50", percentile(from_start[i], 50)}}},
          {"out_of_reach_at_start_seeds", out_at_start[i]},
          {"never_reachable_seeds", never[i]}};
    }
    out[carrier] = c;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ephor-bench-rambo: task ordering, prediction and pose figures of the RAMBO core"};
  std::string json_path;
  unsigned seed = 1;
  int poses = 50, seeds = 10, reach_seeds = 20;
  std::string sections = "ordering,reaching,prediction,pose,live-prediction,reach";
  std::string model_path = "deploy/rambo/target.pbtxt";
  app.add_option("--json", json_path, "write the figures to this JSON file");
  app.add_option("--seed", seed, "first random seed");
  app.add_option("--poses", poses, "images for the pose benchmark")->check(CLI::Range(1, 100000));
  app.add_option("--seeds", seeds, "targets per ordering size and for prediction")
      ->check(CLI::Range(1, 10000));
  app.add_option("--sections", sections,
                 "comma-separated sections to run (default all: ordering,reaching,prediction,pose,"
                 "live-prediction,reach)");
  app.add_option("--model", model_path,
                 "target model file for the reach section (default deploy/rambo/target.pbtxt)");
  app.add_option("--reach-seeds", reach_seeds,
                 "seeds for the reach and live-prediction sections (default 20)")
      ->check(CLI::Range(1, 10000));
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "ephor-bench-rambo: %s\n", e.what());
    return 2;
  }
  nlohmann::json j;
  j["paper"] = {{"pose_s_cm2_16k", 1.0},
                {"dp_trajectories_4_tasks", 32},
                {"exhaustive_trajectories_4_tasks", 64}};
  auto wanted = [&](const std::string& name) {
    return ("," + sections + ",").find("," + name + ",") != std::string::npos;
  };
  if (wanted("ordering")) j["ordering"] = bench_ordering(seeds, seed);
  if (wanted("reaching")) j["reaching"] = bench_reaching();
  if (wanted("prediction")) j["prediction"] = bench_prediction(seeds, seed);
  if (wanted("pose")) j["pose"] = bench_pose(poses, seed);
  try {
    if (wanted("live-prediction"))
      j["live_prediction"] = bench_live_prediction(model_path, reach_seeds);
    if (wanted("reach")) j["reach"] = bench_reach(model_path, reach_seeds);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ephor-bench-rambo: %s\n", e.what());
    return 2;
  }
  if (!json_path.empty()) {
    std::ofstream f(json_path);
    if (!f) {
      std::fprintf(stderr, "ephor-bench-rambo: cannot write %s\n", json_path.c_str());
      return 2;
    }
    f << j.dump(2) << "\n";
  }
  return 0;
}
