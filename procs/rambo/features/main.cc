// ephor-rambo-features: RAMBO's low-level vision (paper section 4) on the
// camera's frames: enhancement by the symmetric nearest-neighbour filter,
// corners (sector-filtered), the corners joined by image edges and the image
// triples (extract_image_features, common/rambo/image_features.h).
//
//   subscribes  CAMERA (camera_frame_t, 8-bit grey)
//   publishes   RAMBO_FEATURES (rambo_features_t, source "features": the triples, and the
//               corners and edges they were made from, for the page), one per frame
//   tasks       features (triggered by CAMERA: always the newest frame)

#include <atomic>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/lcm/mailbox.h"
#include "common/log/log.h"
#include "common/rambo/image_features.h"
#include "common/rambo/rambo_channels.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/time/clock.h"
#include "ephor/camera_frame_t.hpp"
#include "ephor/rambo_features_t.hpp"

int main(int argc, char** argv) {
  using namespace ephor;
  using namespace ephor::rambo;
  block_shutdown_signals();
  CLI::App app{"ephor-rambo-features: image triples from the camera's frames"};
  ProcessArgs args;
  add_process_flags(app, args, "features");
  double duration_s = 0.0;
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    Mailbox<camera_frame_t> frames;
    std::atomic<int64_t> done{0}, empty{0}, bad{0};
    bus.subscribe<camera_frame_t>(ephor::channels::kCamera, [&](const camera_frame_t& m) {
      frames.put(m);
      runtime.trigger("features");
    });
    runtime.add_triggered("features", std::chrono::milliseconds(150), [&] {
      const auto m = frames.take();
      if (!m) return;
      rambo_features_t out{};
      out.utime = m->utime;
      out.frame_index = m->frame_index;
      out.source = "features";
      if (m->width <= 0 || m->height <= 0 ||
          static_cast<int64_t>(m->width) * m->height != m->size ||
          static_cast<int64_t>(m->data.size()) != m->size) {
        ++bad;
        spdlog::warn("CAMERA frame {} from {} refused: {} x {} px does not match its {} bytes",
                     m->frame_index, m->header.sender, m->width, m->height, m->data.size());
        return;
      }
      const cv::Mat grey(m->height, m->width, CV_8UC1, const_cast<uint8_t*>(m->data.data()));
      const ImageFeatures f = extract_image_features(grey);
      for (const ImageTriple& t : f.triples)
        out.triples_px.push_back({t.reference_px.x(), t.reference_px.y(), t.a_px.x(), t.a_px.y(),
                                  t.b_px.x(), t.b_px.y()});
      out.num_triples = static_cast<int32_t>(out.triples_px.size());
      for (const Eigen::Vector2d& c : f.corners_px) out.corners_px.push_back({c.x(), c.y()});
      out.num_corners = static_cast<int32_t>(out.corners_px.size());
      for (const auto& [i, j] : f.edges) out.edges.push_back({i, j});
      out.num_edges = static_cast<int32_t>(out.edges.size());
      if (f.triples.empty() && ++empty % 20 == 1)
        spdlog::info("frame {}: {} ({} such frames)", m->frame_index, f.reason, empty.load());
      ++done;
      bus.publish(rambo::channels::kFeatures, out);
    });
    runtime.start();
    spdlog::info("ready: symmetric nearest-neighbour filter, sector-filtered corners, edges");
    wait_for_shutdown_signal(duration_s);
    runtime.stop();
    spdlog::info("summary: {} frames, {} without triples, {} bad frames", done.load(), empty.load(),
                 bad.load());
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
