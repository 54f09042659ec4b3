// ephor-bench-planner: the planners on the kinematic stand-in (no vision, no
// LCM): escapes per 10 simulated minutes for 1..N sheep with each planner,
// and the time one planning job takes. Issue 3's "bench confine" on the
// full system measures the same with the real simulator; this isolates the
// planner.
//
//   ephor-bench-planner [--minutes 10] [--seeds 3] [--max-sheep 8]
//                       [--lag-s 0.15] [--hide-mm 150] [--arm point|puma]
//                       [--sheep-speed 8] [--json FILE] [--trace-seed N]
//   ephor-bench-planner --start GT.jsonl [--minutes 2] [--arm point|puma] ...
//
// --arm point: the tool is a point moving straight at --arm-speed (300 mm/s,
// the planner's own model of the arm); --arm puma: the PUMA 560 as ephor-arm
// moves it (PumaArmMotion: configuration changes, detours, speed scaling)
// with its tool capped at --arm-speed, its base turned by --base-yaw-deg.
//
// --start: instead of random sheep, one run per planner from the sheep of a
// recorded run's first GROUND_TRUTH message (the file `tools/ephor log
// export run.lcm --channel GROUND_TRUTH --json --out GT.jsonl` writes; its
// first line is used), printing when each escape happened. Asks whether a
// planner with this arm could have kept that run's start (the stand-in has
// no heading wander, collisions or pedestal).
//
// --trace-seed N prints, for the runs with seed N, every goal, change of
// planner phase and escape with the arm's and the sheep's positions: what the
// arm was doing when a sheep left.
//
// Where the arm's time goes: the JSON has, per cell, the simulated time the
// planner spent in each phase (moving, lowering, turning, raising, parking,
// parked, holding) and, with --arm puma, the time of all moves and of the
// joint-space paths among them; --start prints the phase shares.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/runtime/process_args.h"
#include "procs/shepherd/planner/herd_types.h"
#include "procs/shepherd/planner/kinematic_field.h"
#include "procs/shepherd/planner/planner.h"
#include "procs/shepherd/planner/puma_arm_motion.h"
#include "procs/shepherd/planner/recorded_start.h"

namespace {

using ephor::planner::ArmModel;
using ephor::planner::KinematicField;
using ephor::planner::KinematicFieldConfig;

struct Run {
  int escapes = 0;
  int touches = 0;
  int moves = 0;  // --arm puma: moves, joint-space paths among them and their time
  int joint_space_moves = 0;
  double joint_space_s = 0.0;
  double move_s = 0.0;  // --arm puma: the time of every move planned
  std::vector<double> job_us;
  std::vector<double> escape_times_s;
  // Simulated time the planner spent in each phase (PlannerStatus::phase), s:
  // where the arm's time goes (moving, lowering, turning, raising, parking...).
  std::map<std::string, double> phase_s;
};

struct Options {
  double lag_s = 0.15;
  double hide_mm = 150.0;
  std::string arm = "point";
  double sheep_speed_mm_s = 8.0;  // the paper's (003, 4.1); 30 is a stress setting
  double base_yaw_deg = 0.0;      // the PUMA's mounting, Workcell::base_yaw_rad in degrees
  double arm_speed_mm_s = 300.0;  // the point's speed, or the PUMA's tool-speed cap
  int trace_seed = 0;             // runs with this seed print their goals and escapes (0: none)
  bool pedestal = false;          // ephor-sim's bounces off the pedestal and other sheep
  bool collisions = false;
  bool predict_bounces = false;  // PlannerConfig::predict_bounces
  // PlannerConfig::redirect_clearance_mm (0: the tool faces the centre).
  double redirect_clearance_mm = ephor::planner::PlannerConfig{}.redirect_clearance_mm;
  bool touch_toward_centre = false;  // !KinematicFieldConfig::touch_turns_along_tool
};

// Which of ephor-sim's bounces the stand-in has, for the headers.
std::string physics(const Options& o) {
  std::string out = o.pedestal && o.collisions ? "bounces off the pedestal and other sheep"
                    : o.pedestal               ? "bounces off the pedestal"
                    : o.collisions             ? "bounces off other sheep"
                                               : "no collisions, no pedestal";
  if (o.touch_toward_centre) return out + "; a touch turns the sheep at the centre";
  if (o.redirect_clearance_mm <= 0.0) return out + "; sheep sent at the centre";
  return out + "; sheep sent past the pedestal by " +
         std::to_string(static_cast<int>(o.redirect_clearance_mm)) + " mm";
}

// One line of a traced run: a goal sent, a change of phase or an escape,
// with where the arm and every sheep are (F, mm, mm/s).
void trace_line(double t_s, const ephor::planner::PlannerStatus& status,
                const ephor::planner::Scene& scene, const std::optional<ephor::planner::Goal>& goal,
                bool escape) {
  std::fprintf(stderr, "t %7.2f s  %-9s arm (%4.0f, %4.0f)%s", t_s, status.phase.c_str(),
               scene.arm.x_mm, scene.arm.y_mm, scene.arm.lowered ? " down" : "");
  if (goal) {
    std::fprintf(stderr, "  goal %s (%.0f, %.0f) for sheep %d",
                 goal->plane == ephor::planner::Plane::kElevation ? "elevation" : "object",
                 goal->x_mm, goal->y_mm, goal->target);
  }
  for (const auto& s : scene.sheep)
    std::fprintf(stderr, "  sheep %d (%.0f, %.0f) v (%.0f, %.0f)", s.id, s.x_mm, s.y_mm, s.vx_mm_s,
                 s.vy_mm_s);
  std::fprintf(stderr, escape ? "  ESCAPE\n" : "\n");
}

Run run(const std::string& kind, int sheep, uint32_t seed, double seconds, const Options& o,
        const std::vector<ephor::planner::Sheep>* start = nullptr) {
  KinematicFieldConfig fc;
  fc.sheep_speed_mm_s = o.sheep_speed_mm_s;
  fc.workcell.base_yaw_rad = o.base_yaw_deg * std::numbers::pi / 180.0;
  std::shared_ptr<ephor::planner::PumaArmMotion> puma;
  if (o.arm == "puma")
    fc.arm_motion = puma =
        std::make_shared<ephor::planner::PumaArmMotion>(fc.workcell, o.arm_speed_mm_s);
  fc.arm_speed_mm_s = o.arm_speed_mm_s;
  fc.sheep = sheep;
  fc.seed = seed;
  fc.velocity_lag_s = o.lag_s;
  fc.hide_radius_mm = o.hide_mm;
  fc.pedestal = o.pedestal;
  fc.sheep_collisions = o.collisions;
  fc.touch_turns_along_tool = !o.touch_toward_centre;
  KinematicField field = start ? KinematicField(fc, *start) : KinematicField(fc);
  ephor::planner::PlannerConfig pc;
  pc.workcell = fc.workcell;
  pc.predict_bounces = o.predict_bounces;
  pc.redirect_clearance_mm = o.redirect_clearance_mm;
  auto planner = ephor::planner::make_planner(kind, pc);
  ArmModel arm;
  arm.speed_mm_s = o.arm_speed_mm_s;  // what the planner assumes (ephor-planner's arm speed)
  const double dt = 1.0 / 30.0;
  Run out;
  std::string last_phase;
  for (int i = 0; i < static_cast<int>(seconds / dt); ++i) {
    const int escaped_before = field.escapes();
    field.step(dt);
    if (field.escapes() > escaped_before) out.escape_times_s.push_back((i + 1) * dt);
    for (const auto& [id, ok] : field.take_done()) planner->on_motion_done(id, ok);
    const auto scene = field.scene(arm);
    const auto t0 = std::chrono::steady_clock::now();
    const auto goal = planner->plan(scene);
    out.job_us.push_back(
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
    if (goal) field.send(*goal);
    const auto status = planner->status();
    const bool escaped = field.escapes() > escaped_before;
    if (o.trace_seed == static_cast<int>(seed) && (goal || escaped || status.phase != last_phase)) {
      trace_line((i + 1) * dt, status, scene, goal, escaped);
    }
    last_phase = status.phase;
    out.phase_s[status.phase] += dt;
  }
  out.escapes = field.escapes();
  if (puma) {
    out.moves = puma->moves();
    out.joint_space_moves = puma->joint_space_moves();
    out.joint_space_s = puma->joint_space_time_s();
    out.move_s = puma->move_time_s();
  }
  out.touches = field.touches();
  return out;
}

bool write_json(const std::string& path, const nlohmann::json& doc) {
  std::ofstream out(path);
  out << doc.dump(2) << "\n";
  if (!out) std::fprintf(stderr, "cannot write %s\n", path.c_str());
  return static_cast<bool>(out);
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<size_t>(p * static_cast<double>(v.size() - 1));
  return v[i];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ephor-bench-planner: planners on the kinematic stand-in"};
  double minutes = 10.0;
  int seeds = 3;
  int max_sheep = 8;
  Options o;
  std::string json_path;
  std::vector<std::string> kinds = ephor::planner::planner_kinds();
  app.add_option("--minutes", minutes, "simulated minutes per run")->check(CLI::Range(0.1, 600.0));
  app.add_option("--seeds", seeds, "runs (seeds 1..N) per planner and sheep count")
      ->check(CLI::Range(1, 100));
  app.add_option("--max-sheep", max_sheep, "sheep counts 1..N")->check(CLI::Range(1, 20));
  app.add_option("--lag-s", o.lag_s, "sensing lag of a turn, s")->check(CLI::Range(0.0, 5.0));
  app.add_option("--hide-mm", o.hide_mm, "sheep within this of the lowered tool are hidden, mm")
      ->check(CLI::Range(0.0, 1000.0));
  app.add_option("--arm", o.arm, "point: straight lines at 300 mm/s; puma: ephor-arm's motions")
      ->check(CLI::IsMember({"point", "puma"}));
  app.add_option("--sheep-speed", o.sheep_speed_mm_s, "mean sheep speed, mm/s")
      ->check(CLI::Range(1.0, 200.0));
  app.add_option("--planner", kinds, "planner kinds to run (default: all)")
      ->check(CLI::IsMember(ephor::planner::planner_kinds()));
  app.add_option("--json", json_path, "write the results here");
  app.add_flag(
      "--pedestal", o.pedestal,
      "sheep bounce off the PUMA's pedestal, as in ephor-sim (default: they pass through)");
  app.add_flag(
      "--predict-bounces", o.predict_bounces,
      "the planner chooses whom to save by bounced paths (PlannerConfig::predict_bounces)");
  app.add_flag("--collisions", o.collisions,
               "sheep bounce off each other, as in ephor-sim (default: they pass through)");
  app.add_option("--redirect-clearance-mm", o.redirect_clearance_mm,
                 "the tool sends a sheep past the pedestal's axis by this, mm (0: at the centre)")
      ->check(CLI::Range(0.0, 400.0));
  app.add_flag("--touch-toward-centre", o.touch_toward_centre,
               "a touched sheep turns at the centre whatever the tool's orientation (the "
               "stand-in before 2026-11-28)");
  app.add_option("--base-yaw-deg", o.base_yaw_deg,
                 "--arm puma: the arm's base turned by this about the vertical, deg (where joint "
                 "1's wedge falls)")
      ->check(CLI::Range(-180.0, 180.0));
  app.add_option("--arm-speed", o.arm_speed_mm_s,
                 "the point's speed or the PUMA's tool-speed cap, mm/s (the arm's default: 300)")
      ->check(CLI::Range(10.0, 2000.0));
  app.add_option("--trace-seed", o.trace_seed,
                 "print every goal, phase change and escape of the runs with this seed to "
                 "stderr (with --start: 1)")
      ->check(CLI::Range(1, 100));
  std::string start_path;
  app.add_option("--start", start_path,
                 "one run per planner from the sheep of this GROUND_TRUTH export (first line)")
      ->check(CLI::ExistingFile);
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;

  if (!start_path.empty()) {
    std::vector<ephor::planner::Sheep> start;
    try {
      start = ephor::planner::sheep_from_ground_truth_file(start_path);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "--start: %s\n", e.what());
      return 1;
    }
    std::printf(
        "%zu sheep from %s, %.1f simulated min (lag %.2f s, hidden %.0f mm; arm %s at %.0f mm/s, "
        "base yaw %.0f deg; %s)\n",
        start.size(), start_path.c_str(), minutes, o.lag_s, o.hide_mm, o.arm.c_str(),
        o.arm_speed_mm_s, o.base_yaw_deg, physics(o).c_str());
    nlohmann::json runs = nlohmann::json::array();
    for (const std::string& kind : kinds) {
      const Run r = run(kind, static_cast<int>(start.size()), 1, minutes * 60.0, o, &start);
      std::printf("%-10s escapes %d, turns %d; escapes at", kind.c_str(), r.escapes, r.touches);
      for (const double t : r.escape_times_s) std::printf(" %.1f", t);
      std::printf(r.escape_times_s.empty() ? " none\n" : " s\n");
      std::printf("%-10s time by phase:", "");
      for (const auto& [phase, t] : r.phase_s)
        std::printf(" %s %.0f%%", phase.c_str(), 100.0 * t / (minutes * 60.0));
      std::printf("\n");
      runs.push_back({{"planner", kind},
                      {"escapes", r.escapes},
                      {"touches", r.touches},
                      {"escape_times_s", r.escape_times_s},
                      {"phase_time_s", r.phase_s}});
    }
    const nlohmann::json doc{{"start", start_path},
                             {"arm", o.arm},
                             {"arm_speed_mm_s", o.arm_speed_mm_s},
                             {"base_yaw_deg", o.base_yaw_deg},
                             {"pedestal", o.pedestal},
                             {"collisions", o.collisions},
                             {"minutes", minutes},
                             {"runs", runs}};
    return json_path.empty() || write_json(json_path, doc) ? 0 : 1;
  }

  nlohmann::json results = nlohmann::json::array();
  std::printf(
      "escapes per 10 simulated min (mean of %d seeds, %.1f min each; lag %.2f s, hidden %.0f "
      "mm; arm %s at %.0f mm/s, base yaw %.0f deg; sheep %.0f mm/s; %s)\n",
      seeds, minutes, o.lag_s, o.hide_mm, o.arm.c_str(), o.arm_speed_mm_s, o.base_yaw_deg,
      o.sheep_speed_mm_s, physics(o).c_str());
  std::printf("%-10s", "planner");
  for (int n = 1; n <= max_sheep; ++n) std::printf("  %2d sheep", n);
  std::printf("   job p50/p99/max us\n");
  for (const std::string& kind : kinds) {
    std::printf("%-10s", kind.c_str());
    std::vector<double> all_us;
    for (int n = 1; n <= max_sheep; ++n) {
      int escapes = 0;
      int touches = 0;
      int moves = 0;
      int joint_space_moves = 0;
      double joint_space_s = 0.0;
      double move_s = 0.0;
      std::map<std::string, double> phase_s;
      for (int s = 1; s <= seeds; ++s) {
        const Run r = run(kind, n, static_cast<uint32_t>(s), minutes * 60.0, o);
        escapes += r.escapes;
        touches += r.touches;
        moves += r.moves;
        joint_space_moves += r.joint_space_moves;
        joint_space_s += r.joint_space_s;
        move_s += r.move_s;
        for (const auto& [phase, t] : r.phase_s) phase_s[phase] += t;
        all_us.insert(all_us.end(), r.job_us.begin(), r.job_us.end());
      }
      const double per10 = static_cast<double>(escapes) / seeds * (10.0 / minutes);
      std::printf("  %8.2f", per10);
      results.push_back({{"planner", kind},
                         {"sheep", n},
                         {"seeds", seeds},
                         {"minutes", minutes},
                         {"escapes_total", escapes},
                         {"escapes_per_10min", per10},
                         {"touches_total", touches},
                         {"arm_moves_total", moves},
                         {"joint_space_moves_total", joint_space_moves},
                         {"joint_space_time_s_total", joint_space_s},
                         {"arm_move_time_s_total", move_s},
                         {"phase_time_s_total", phase_s}});
    }
    std::printf("   %.1f/%.1f/%.1f\n", percentile(all_us, 0.5), percentile(all_us, 0.99),
                percentile(all_us, 1.0));
  }
  const nlohmann::json doc{{"lag_s", o.lag_s},
                           {"hide_mm", o.hide_mm},
                           {"arm", o.arm},
                           {"arm_speed_mm_s", o.arm_speed_mm_s},
                           {"base_yaw_deg", o.base_yaw_deg},
                           {"sheep_speed_mm_s", o.sheep_speed_mm_s},
                           {"pedestal", o.pedestal},
                           {"collisions", o.collisions},
                           {"runs", results}};
  if (!json_path.empty() && !write_json(json_path, doc)) return 1;
  return 0;
}
