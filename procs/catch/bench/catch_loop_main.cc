// ephor-catch-loop: the whole catching system in simulated time (CatchLoop):
// the simulator's world, vision, world model, Prim and the arm as ephor-arm
// executes a cup goal, judged by the simulator and scored by the monitor.
// Deterministic and free of the machine's load, so a change to Prim or the
// world model is judged by balls caught of oracle_reachable:
//
//   ephor-catch-loop --seeds 1-5 --balls 20 [--prim prediction|oracle]
//                    [--true-centre] [--commit-ahead-s S ...] [--json F]
//
// Output: a line per ball with --verbose, a line per seed, and a total line
// (JSON with --json: the totals and each seed's monitor summary).

#include <chrono>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/catch/board_file.h"
#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/geometry/workcell_file.h"
#include "common/runtime/process_args.h"
#include "procs/catch/bench/catch_loop.h"

namespace {

// "3" or "1-5" or "1,4,7".
std::vector<uint64_t> parse_seeds(const std::string& text) {
  std::vector<uint64_t> out;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = text.find(',', start);
    const std::string part =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const size_t dash = part.find('-');
    try {
      if (dash == std::string::npos) {
        out.push_back(std::stoull(part));
      } else {
        const uint64_t a = std::stoull(part.substr(0, dash)),
                       b = std::stoull(part.substr(dash + 1));
        if (b < a || b - a > 10000) throw std::invalid_argument("range");
        for (uint64_t s = a; s <= b; ++s) out.push_back(s);
      }
    } catch (const std::exception&) {
      throw std::invalid_argument("--seeds '" + text +
                                  "': want a seed, a range A-B or a comma-separated list");
    }
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ephor;
  using namespace ephor::catching;
  CLI::App app{"ephor-catch-loop: the catching system in simulated time, caught of reachable"};
  std::string seeds_text = "1-5", json_path, prim = "cover";
  std::string board_path = "deploy/catch/board.pbtxt",
              workcell_path = "deploy/catch/workcell.pbtxt";
  CatchLoopOptions o;
  bool verbose = false;
  app.add_option("--seeds", seeds_text, "seeds: S, A-B or a list S1,S2 (default 1-5)");
  app.add_option("--balls", o.balls, "balls per seed (default 20)")->check(CLI::Range(1, 10000));
  app.add_option("--prim", prim,
                 "cover (ephor-catch-prim on the cover of the prediction's spread, as "
                 "deploy/catch.pbtxt runs it; the default), prediction (on the mean's prediction: "
                 "the world model without --spread-samples) or oracle (the true catch point at "
                 "release)")
      ->check(CLI::IsMember({"prediction", "cover", "oracle"}));
  app.add_option("--spread-samples", o.model.spread.samples,
                 "--prim cover: states drawn for the exit's spread (default 32)")
      ->check(CLI::Range(1, 10000));
  app.add_option("--capture-radius-mm", o.model.spread.capture_radius_mm,
                 "--prim cover: the cup's capture radius for the cover (default 30)")
      ->check(CLI::Range(1.0, 1000.0));
  app.add_flag("--true-centre", o.true_centre,
               "the world model gets the ball centre's true projection (the vision's ceiling)");
  app.add_option("--commit-ahead-s", o.tuning.commit_ahead_s, "Prim: ephor-catch-prim's flag")
      ->check(CLI::Range(0.05, 10.0));
  app.add_option("--reaim-ms", o.tuning.reaim_ms, "Prim: ephor-catch-prim's flag")
      ->check(CLI::Range(10.0, 10000.0));
  app.add_option("--resend-mm", o.tuning.resend_mm, "Prim: ephor-catch-prim's flag")
      ->check(CLI::Range(0.0, 1000.0));
  app.add_option("--freeze-ms", o.tuning.freeze_ms, "Prim: ephor-catch-prim's flag")
      ->check(CLI::Range(0.0, 10000.0));
  app.add_option("--move-s-per-sqrt-mm", o.tuning.move_s_per_sqrt_mm,
                 "Prim: ephor-catch-prim's flag (commit late; 0 = off)")
      ->check(CLI::Range(0.0, 10.0));
  app.add_option("--max-sigma-mm", o.tuning.max_sigma_mm,
                 "Prim: ephor-catch-prim's flag (with --prim cover the sigma is the spread's)")
      ->check(CLI::Range(0.0, 100000.0));
  app.add_option("--commit-margin-s", o.tuning.commit_margin_s, "Prim: ephor-catch-prim's flag")
      ->check(CLI::Range(0.0, 10.0));
  app.add_option("--hold-ms", o.tuning.hold_ms, "Prim: ephor-catch-prim's flag")
      ->check(CLI::Range(0.0, 10000.0));
  double perception_ms = 1e3 * o.perception_latency_s, command_ms = 1e3 * o.command_latency_s,
         trajectory_ms = 1e3 * o.trajectory_latency_s;
  app.add_option("--perception-latency-ms", perception_ms, "frame capture to Prim, ms (default 5)")
      ->check(CLI::Range(0.0, 1000.0));
  app.add_option("--command-latency-ms", command_ms,
                 "Prim's goal to ephor-arm's planning, ms (default 10)")
      ->check(CLI::Range(0.0, 1000.0));
  app.add_option("--trajectory-latency-ms", trajectory_ms,
                 "ephor-arm's plan to the servo following it, ms (default 4)")
      ->check(CLI::Range(0.0, 1000.0));
  app.add_option("--board", board_path, "board file (common/catch/board.proto)");
  app.add_option("--workcell", workcell_path, "work cell file");
  app.add_flag("--verbose", verbose, "a line per missed ball");
  app.add_flag("--trace", o.trace, "a line per Prim cycle with a ball and per goal");
  app.add_option("--json", json_path, "write the totals and each seed's summary here");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  o.perception_latency_s = perception_ms / 1e3;
  o.command_latency_s = command_ms / 1e3;
  o.trajectory_latency_s = trajectory_ms / 1e3;
  o.prim = prim == "oracle"  ? PrimMode::kOracle
           : prim == "cover" ? PrimMode::kCover
                             : PrimMode::kPrediction;

  if (!json_path.empty()) {
    std::ofstream probe(json_path, std::ios::app);
    if (!probe) {
      std::cerr << "ephor-catch-loop: --json " << json_path << ": cannot write there\n";
      return 2;
    }
  }
  try {
    const std::vector<uint64_t> seeds = parse_seeds(seeds_text);
    const BoardSpec board = load_board_file(resolve_repo_path(board_path));
    const geometry::Workcell workcell =
        geometry::load_workcell_file(resolve_repo_path(workcell_path));
    int balls = 0, caught = 0, reachable = 0, caught_reachable = 0;
    std::map<std::string, int> kinds;
    nlohmann::json runs = nlohmann::json::array();
    for (const uint64_t seed : seeds) {
      o.seed = seed;
      const auto t0 = std::chrono::steady_clock::now();
      CatchLoopResult r;
      try {
        r = CatchLoop(board, workcell, o).run();
      } catch (const std::runtime_error& e) {
        std::cout << "seed " << seed << ": not run: " << e.what() << "\n";
        runs.push_back({{"seed", seed}, {"error", e.what()}});
        continue;
      }
      const double wall_s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      balls += r.balls;
      caught += r.caught;
      reachable += r.oracle_reachable;
      caught_reachable += r.caught_reachable;
      std::string kind_text;
      if (r.summary.contains("missed_kinds_oracle_reachable"))
        for (const auto& [k, n] : r.summary["missed_kinds_oracle_reachable"].items()) {
          kinds[k] += n.get<int>();
          kind_text += fmt::format("{}{} {}", kind_text.empty() ? "" : ", ", n.get<int>(), k);
        }
      if (verbose && r.summary.contains("missed"))
        for (const auto& b : r.summary["missed"]) std::cout << "  " << b.dump() << "\n";
      std::cout << fmt::format(
          "seed {}: {} balls, {} caught, {} oracle-reachable, {} of them caught; reachable "
          "misses: {}; {} goals, {} refused, {} servo faults ({:.0f} s)\n",
          seed, r.balls, r.caught, r.oracle_reachable, r.caught_reachable,
          kind_text.empty() ? "none" : kind_text, r.goals, r.plans_refused, r.servo_faults, wall_s);
      nlohmann::json j = r.summary;
      j["goals"] = r.goals;
      j["plans_refused"] = r.plans_refused;
      j["servo_faults"] = r.servo_faults;
      runs.push_back(j);
    }
    std::string kind_text;
    for (const auto& [k, n] : kinds)
      kind_text += fmt::format("{}{} {}", kind_text.empty() ? "" : ", ", n, k);
    std::cout << fmt::format(
        "total: {} balls, {} caught, {} oracle-reachable, {} of them caught ({:.0f} %); "
        "reachable misses: {}\n",
        balls, caught, reachable, caught_reachable,
        reachable > 0 ? 100.0 * caught_reachable / reachable : 0.0,
        kind_text.empty() ? "none" : kind_text);
    if (!json_path.empty()) {
      nlohmann::json out{{"prim", prim},
                         {"true_centre", o.true_centre},
                         {"balls", balls},
                         {"caught", caught},
                         {"oracle_reachable", reachable},
                         {"caught_of_oracle_reachable", caught_reachable},
                         {"missed_kinds_oracle_reachable", kinds},
                         {"runs", runs}};
      std::ofstream(json_path) << out.dump(1) << "\n";
    }
  } catch (const ephor::ConfigError& e) {
    std::cerr << "ephor-catch-loop: " << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << "ephor-catch-loop: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ephor-catch-loop: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
