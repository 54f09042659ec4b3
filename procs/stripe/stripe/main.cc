// ephor-stripe-stripe: the `stripe` process of the light-stripe system (paper
// 004, section 2: the vision module's "connectivity algorithm ... specially
// modified for use with stripes that run in a generally top-to-bottom
// orientation. It finds the tallest stripe in the image, throwing away spurs
// and other noise"): per stripe image, threshold, the tallest top-to-bottom
// chain of runs, its centre line to sub-pixel per row (--method: the paper's
// run midpoint, a centroid, a Gaussian fit or Steger's line point) and its
// width (common/stripe StripeExtractor).
//
//   ephor-stripe-stripe [--method run|centroid|gaussian|steger] [--threshold T]
//
//   subscribes  STRIPE_IMAGE (stripe_image_t; the spot images of calibration are skipped)
//   publishes   STRIPE_PROFILE (stripe_profile_t), one per stripe image, in arrival order
//   tasks       extract (triggered by each image)
//
// Every image of a scan matters: images are queued (up to 64), not
// replaced by the newest.

#include <atomic>
#include <ctime>
#include <deque>
#include <iostream>
#include <mutex>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/lcm/bus.h"
#include "common/lcm/inbox.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/stripe/stripe_channels.h"
#include "common/stripe/stripe_extractor.h"
#include "common/stripe/stripe_messages.h"
#include "ephor/stripe_capture_t.hpp"
#include "ephor/stripe_image_t.hpp"
#include "ephor/stripe_profile_t.hpp"

namespace {

using namespace ephor;
using namespace ephor::stripe;

double thread_cpu_us() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) * 1e-3;
}

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{"ephor-stripe-stripe: the stripe's centre line and width per row of each image"};
  ProcessArgs args;
  add_process_flags(app, args, "stripe");
  std::string method = "gaussian";
  int threshold = 60;
  double duration_s = 0.0;
  app.add_option("--method", method,
                 "centre of each row: run (the paper's run midpoint), centroid, gaussian "
                 "(default) or steger");
  app.add_option("--threshold", threshold, "grey level of the threshold (default 60)")
      ->check(CLI::Range(1, 255));
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)")
      ->check(CLI::Range(0.0, 1e7));
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  StripeExtractorOptions options;
  try {
    options.method = parse_centre_method(method);
  } catch (const std::invalid_argument&) {
    std::cerr << "ephor-stripe-stripe: --method " << method
              << ": unknown (run, centroid, gaussian, steger)\n";
    return 2;
  }
  options.threshold = threshold;

  try {
    const StripeExtractor extractor(options);
    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    Inbox<stripe_image_t> images_in(64);
    std::atomic<int64_t> profiles{0}, bad{0};

    bus.subscribe<stripe_image_t>(channels::kImage, [&](const stripe_image_t& m) {
      if (m.mode != stripe_capture_t::MODE_STRIPE) return;  // the spot, for calibration
      if (!images_in.push(m))
        spdlog::warn("image queue full: the oldest image dropped ({} so far)", images_in.dropped());
      runtime.trigger("extract");
    });

    runtime.add_triggered("extract", std::chrono::milliseconds(100), [&] {
      for (const stripe_image_t& m : images_in.drain()) {
        std::string why;
        const cv::Mat image = image_of(m, &why);
        if (image.empty()) {
          const int64_t n = ++bad;
          if (n <= 10 || n % 100 == 0)
            spdlog::warn("STRIPE_IMAGE {} from {} refused: {} ({} so far)", m.image_index,
                         m.header.sender, why, n);
          continue;
        }
        const double c0 = thread_cpu_us();
        const Stripe stripe = extractor.extract(image);
        const double cpu = thread_cpu_us() - c0;
        stripe_profile_t p = profile_of(m, stripe, options);
        p.cpu_us = static_cast<float>(cpu);
        bus.publish(channels::kProfile, p);
        ++profiles;
        spdlog::debug("image {} (scan {} stripe {}): {} rows, {} runs dropped, {:.0f} us",
                      m.image_index, m.scan_id, m.stripe_index, p.num_rows, p.runs_dropped, cpu);
      }
    });

    runtime.start();
    spdlog::info("ready: {} centres, threshold {}", centre_method_name(options.method), threshold);
    wait_for_shutdown_signal(duration_s);
    runtime.stop();
    spdlog::info("summary: {} profiles, {} images refused, {} dropped", profiles.load(), bad.load(),
                 images_in.dropped());
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
