// ephor-stripe-range: the `range` process of the light-stripe system (paper
// 004, section 2): each stripe profile's points through the collineation K
// (K from R = C P^-1 and Q = S^-1 C P^-1, C = T C_T and S = T S_T with T the
// flange pose the software's arm model gives for the image's joint
// readings) to 3-D points in the table frame, published per stripe, and
// accumulated into one cloud per scan (CloudAccumulator), written as PLY
// (PCL's binary float x y z, mm, table frame) when the scan is complete.
//
//   ephor-stripe-range [--calibration FILE] [--robot-seed N] [--workcell FILE] [--out CLOUD.ply]
//
//   subscribes  STRIPE_PROFILE (stripe_profile_t), STRIPE_SCAN (stripe_scan_t)
//   publishes   STRIPE_POINTS (stripe_points_t), one per profile;
//               STRIPE_CLOUD (stripe_cloud_t), once per complete scan (again
//               when the planner says CAPTURED again for a finished scan)
//   tasks       range (triggered by each profile), cloud (200 ms: complete scans, files)
//
// --calibration: the file ephor-stripe-calibrate wrote for this robot
// (--robot-seed: a file measured on another robot is refused, exit 2);
// without it, the nominal arm and the cage from the mechanical drawings.

#include <atomic>
#include <deque>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/geometry/workcell_file.h"
#include "common/lcm/bus.h"
#include "common/lcm/inbox.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/stripe/calibration_file.h"
#include "common/stripe/cloud_file.h"
#include "common/stripe/range_finder.h"
#include "common/stripe/stripe_channels.h"
#include "common/stripe/stripe_messages.h"
#include "common/time/clock.h"
#include "ephor/stripe_cloud_t.hpp"
#include "ephor/stripe_points_t.hpp"
#include "ephor/stripe_profile_t.hpp"
#include "ephor/stripe_scan_t.hpp"
#include "procs/stripe/range/cloud_accumulator.h"
#include "procs/stripe/range/range_messages.h"

namespace {

using namespace ephor;
using namespace ephor::stripe;

double now_s() { return static_cast<double>(mono_ns()) * 1e-9; }

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{"ephor-stripe-range: stripe profiles to 3-D points in the table frame, clouds"};
  ProcessArgs args;
  add_process_flags(app, args, "range");
  std::string calibration_path, workcell_path = "deploy/stripe/workcell.pbtxt", out_path;
  int robot_seed = 0;
  double missing_timeout_s = 5.0, duration_s = 0.0;
  app.add_option("--calibration", calibration_path,
                 "calibration file (common/stripe/stripe_calibration.proto; default: the nominal "
                 "arm and the cage from the drawings)");
  app.add_option("--robot-seed", robot_seed,
                 "the robot this is (the calibration file must have been measured on it)")
      ->check(CLI::Range(0, 1000000));
  app.add_option("--workcell", workcell_path,
                 "work cell file (default deploy/stripe/workcell.pbtxt)");
  app.add_option("--out", out_path, "write each complete scan's cloud to this PLY file");
  app.add_option("--missing-timeout-s", missing_timeout_s,
                 "complete a scan this long after its last image even with stripes unheard "
                 "(default 5)")
      ->check(CLI::Range(0.1, 600.0));
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)")
      ->check(CLI::Range(0.0, 1e7));
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    const geometry::Workcell workcell =
        geometry::load_workcell_file(resolve_repo_path(workcell_path));
    const StripeCalibration calibration = calibration_from_flags(calibration_path, robot_seed);
    const RangeFinder finder(StripeWorkcell::from_workcell(workcell), calibration.arm_model(),
                             calibration.sensor);
    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    std::mutex mutex;
    Inbox<stripe_profile_t> profiles_in(256);
    CloudAccumulator clouds(missing_timeout_s);
    FinishedClouds done;  // finished scans' messages (repeated on request)
    std::atomic<int64_t> stripes{0}, points{0}, bad{0};

    bus.subscribe<stripe_profile_t>(channels::kProfile, [&](const stripe_profile_t& m) {
      profiles_in.push(m);
      runtime.trigger("range");
    });
    bus.subscribe<stripe_scan_t>(channels::kScan, [&](const stripe_scan_t& m) {
      std::lock_guard<std::mutex> lock(mutex);
      // A finished scan: the planner has not heard the cloud, say it again.
      if (stripe_cloud_t* again = on_scan(m, clouds, done, now_s()))
        bus.publish(channels::kCloud, *again);
    });

    runtime.add_triggered("range", std::chrono::milliseconds(100), [&] {
      for (const stripe_profile_t& m : profiles_in.drain()) {
        std::string why;
        std::optional<RangedStripe> ranged = range_profile(m, finder, &why);
        if (!ranged) {
          const int64_t n = ++bad;
          if (n <= 10 || n % 100 == 0)
            spdlog::warn("STRIPE_PROFILE {} from {} refused: {} ({} so far)", m.image_index,
                         m.header.sender, why, n);
          continue;
        }
        {
          std::lock_guard<std::mutex> lock(mutex);
          if (!add_to_cloud(*ranged, clouds) && m.scan_id > 0) {
            spdlog::debug("scan {} stripe {}: a repeat, not added", m.scan_id, m.stripe_index);
          }
        }
        stripe_points_t& out = ranged->message;
        bus.publish(channels::kPoints, out);
        ++stripes;
        points += out.num_points;
      }
    });

    runtime.add_periodic("cloud", std::chrono::milliseconds(200), [&] {
      std::vector<CompletedCloud> complete;
      {
        std::lock_guard<std::mutex> lock(mutex);
        complete = clouds.take_complete(now_s());
      }
      for (const CompletedCloud& c : complete) {
        stripe_cloud_t m = cloud_message_of(c);
        m.utime = wall_us();
        if (!out_path.empty()) {
          try {
            save_cloud_ply(out_path, c.points);
            m.path = out_path;
          } catch (const CloudFileError& e) {
            m.error = e.what();
            spdlog::error("{}", e.what());
          }
        }
        spdlog::info("scan {}: cloud of {} points from {} stripes ({} missing){}", c.scan_id,
                     m.points, c.stripes, c.stripes_missing,
                     m.path.empty() ? "" : ", written to " + m.path);
        bus.publish(channels::kCloud, m);
        std::lock_guard<std::mutex> lock(mutex);
        remember_cloud(done, m);
      }
    });

    runtime.start();
    spdlog::info("ready: {}{}", calibration.measured,
                 out_path.empty() ? "" : ", clouds to " + out_path);
    wait_for_shutdown_signal(duration_s);
    runtime.stop();
    spdlog::info("summary: {} stripes ranged, {} points, {} profiles refused", stripes.load(),
                 points.load(), bad.load());
  } catch (const ConfigError& e) {
    std::cerr << "ephor-stripe-range: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
