// ephor-display: a live web page for watching and steering the system (paper
// 003 section 3.2, the display process). It only listens to the bus, keeps the
// newest message of every channel, and serves:
//   GET  /                 the page (embedded at build time from web/)
//   GET  /api/state        overlay state, score, task table, rates (JSON)
//   GET  /api/frame.jpg    the newest camera frame as JPEG
//   POST /api/cmd?cmd=C&…  a control (validated; HTTP 400 with the reason, nothing sent)
//   GET  /api/debug        the newest message of every channel heard (JSON download)
//   GET  /api/rates        messages per second per channel (JSON)
// The page polls state and frame: each answer is the newest data (no queue to
// fall behind on), a slow browser simply gets fewer updates, and no server
// thread is held per client. Frames are JPEG-encoded only when asked for, at
// most --max-fps times a second, so an unwatched display costs almost nothing.
//
//   ephor-display [--http-address 127.0.0.1] [--http-port 8080] [--calibration FILE]
//                 [--sim-seed N] [--max-fps 15]

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/calibration/field_calibration.h"
#include "common/geometry/workcell.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/runtime/channels.h"
#include "common/runtime/process_args.h"
#include "common/time/clock.h"
#include "ephor/estop_t.hpp"
#include "procs/shared/display/command_validator.h"
#include "procs/shared/display/display_state.h"
#include "procs/shared/display/frame_encoder.h"
#include "procs/shared/display/lcm_json.h"
#include "procs/shared/display/rate_meter.h"
#include "procs/shared/display/web_assets.h"

// Last: httplib.h pulls in <resolv.h>, whose `_res` macro breaks Eigen headers included after it.
#include <httplib.h>

namespace {

using namespace ephor;
using ephor::display::Controls;

std::filesystem::path repo_dir() {
  if (const char* env = std::getenv("EPHOR_SOURCE_DIR"); env != nullptr && *env != '\0') return env;
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return ".";
  return exe.parent_path().parent_path().parent_path();
}

// The newest message of every channel, for the debug dump.
class Snapshot {
 public:
  template <class T>
  void put(const std::string& channel, const T& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    newest_[channel] = [msg]() { return nlohmann::json(msg); };
  }
  nlohmann::json to_json() const {
    std::map<std::string, std::function<nlohmann::json()>> copy;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      copy = newest_;
    }
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [channel, fn] : copy) j[channel] = fn();
    return j;
  }

 private:
  mutable std::mutex mutex_;
  std::map<std::string, std::function<nlohmann::json()>> newest_;
};

// Everything the HTTP threads and the LCM thread share.
struct Shared {
  std::mutex mutex;  // guards state, controls, the *_known flags and the newest frame
  std::unique_ptr<display::DisplayState> state;
  Controls controls;
  bool vision_known = false;  // controls.vision came from a VISION_CMD or BLOBS
  bool sim_known = false;
  bool planner_known = false;
  std::shared_ptr<const camera_frame_t> frame;

  std::mutex jpeg_mutex;  // guards encoder and the cached JPEG
  display::FrameEncoder encoder{75};
  std::string jpeg;
  int64_t jpeg_frame_index = -1;
  int64_t jpeg_mono_ns = 0;
  double jpeg_tokens = 2.0;  // token bucket: max_fps encodes/s on average, bursts of 2
  uint64_t jpegs_encoded = 0;
  std::atomic<int64_t> last_request_mono_ns{0};

  std::mutex rates_mutex;
  display::RateMeter rates{2.0};
};

const std::vector<std::string>& heard_channels() {
  static const std::vector<std::string> list = {
      channels::kCamera,      channels::kGroundTruth, channels::kSimCmd,        channels::kBlobs,
      channels::kVisionCmd,   channels::kObjects,     channels::kPlannerStatus, channels::kArmGoal,
      channels::kMotionDone,  channels::kArmCmd,      channels::kArmAck,        channels::kArmState,
      channels::kSchedStatus, channels::kPlannerCmd,  channels::kDisplayBox};
  return list;
}

void subscribe_all(Bus& bus, Shared& sh, Snapshot& snap) {
  bus.subscribe<camera_frame_t>(channels::kCamera, [&](const camera_frame_t& m) {
    auto frame = std::make_shared<const camera_frame_t>(m);
    std::lock_guard<std::mutex> lock(sh.mutex);
    sh.frame = frame;
    sh.state->on_frame(m.frame_index, m.width, m.height, wall_us());
    // The dump shows a frame's fields, not its pixels: keep no second copy of them.
    camera_frame_t fields;
    fields.utime = m.utime;
    fields.header = m.header;
    fields.frame_index = m.frame_index;
    fields.width = m.width;
    fields.height = m.height;
    fields.size = m.size;
    snap.put(channels::kCamera, fields);
  });
  bus.subscribe<shepherd_blobs_t>(channels::kBlobs, [&](const shepherd_blobs_t& m) {
    display::BlobsView b;
    b.frame_index = m.frame_index;
    b.mode = m.mode;
    b.scan = m.scan;
    b.threshold = m.threshold;
    b.processing_us = static_cast<double>(m.processing_us);
    for (const auto& x : m.blobs) b.blobs.push_back({x.u, x.v, x.area});
    snap.put(channels::kBlobs, m);
    std::lock_guard<std::mutex> lock(sh.mutex);
    sh.state->on_blobs(std::move(b), wall_us());
    if (!sh.vision_known) {  // nobody commanded vision yet: take over its current mode
      sh.controls.vision.mode = m.mode;
      sh.controls.vision.scan = m.scan;
      sh.vision_known = true;
    }
  });
  bus.subscribe<shepherd_vision_cmd_t>(channels::kVisionCmd, [&](const shepherd_vision_cmd_t& m) {
    snap.put(channels::kVisionCmd, m);
    std::lock_guard<std::mutex> lock(sh.mutex);
    sh.controls.vision = {m.paused != 0, m.mode, m.scan, m.threshold};
    sh.vision_known = true;
  });
  bus.subscribe<shepherd_objects_t>(channels::kObjects, [&](const shepherd_objects_t& m) {
    std::vector<display::TrackedObject> objs;
    objs.reserve(m.objects.size());
    for (const auto& o : m.objects) {
      objs.push_back({o.id, o.state, o.u, o.v, o.vu_px_s, o.vv_px_s, o.since_seen_s, o.area});
    }
    snap.put(channels::kObjects, m);
    std::lock_guard<std::mutex> lock(sh.mutex);
    sh.state->on_objects(std::move(objs), wall_us());
  });
  bus.subscribe<shepherd_planner_status_t>(
      channels::kPlannerStatus, [&](const shepherd_planner_status_t& m) {
        snap.put(channels::kPlannerStatus, m);
        std::lock_guard<std::mutex> lock(sh.mutex);
        sh.state->on_planner({m.planner, m.phase, m.target_object, m.intercept_u, m.intercept_v,
                              m.intercept_time_s, m.planning_us, m.goal_id},
                             wall_us());
        if (!sh.planner_known && !m.planner.empty()) {
          sh.controls.planner = m.planner;
          sh.planner_known = true;
        }
      });
  bus.subscribe<shepherd_planner_cmd_t>(channels::kPlannerCmd,
                                        [&](const shepherd_planner_cmd_t& m) {
                                          snap.put(channels::kPlannerCmd, m);
                                          std::lock_guard<std::mutex> lock(sh.mutex);
                                          sh.controls.planner = m.planner;
                                          sh.planner_known = true;
                                        });
  bus.subscribe<arm_state_t>(channels::kArmState, [&](const arm_state_t& m) {
    snap.put(channels::kArmState, m);
    std::lock_guard<std::mutex> lock(sh.mutex);
    sh.state->on_arm({m.u, m.v, m.theta_rad, m.z_mm, m.moving != 0, m.speed_mm_s}, wall_us());
  });
  bus.subscribe<shepherd_ground_truth_t>(
      channels::kGroundTruth, [&](const shepherd_ground_truth_t& m) {
        display::TruthView t;
        t.escapes = m.escapes;
        t.saves = m.saves;
        t.sim_time_s = m.sim_time_s;
        for (const auto& s : m.sheep)
          t.sheep.push_back({s.id, s.u, s.v, s.visible != 0, s.on_field != 0});
        snap.put(channels::kGroundTruth, m);
        std::lock_guard<std::mutex> lock(sh.mutex);
        if (!sh.sim_known) {  // nobody commanded the simulator yet: its herd as it is
          sh.controls.sim.sheep = m.num_sheep;
          sh.sim_known = true;
        }
        sh.state->on_truth(std::move(t), wall_us());
      });
  bus.subscribe<shepherd_sim_cmd_t>(channels::kSimCmd, [&](const shepherd_sim_cmd_t& m) {
    snap.put(channels::kSimCmd, m);
    std::lock_guard<std::mutex> lock(sh.mutex);
    sh.controls.sim = {m.sheep, m.seed};
    sh.sim_known = true;
  });
  bus.subscribe<sched_status_t>(channels::kSchedStatus, [&](const sched_status_t& m) {
    display::HostSched h;
    h.host = m.host;
    h.rt = m.rt != 0;
    for (float x : m.cpu_utilisation) h.cpu_utilisation.push_back(static_cast<double>(x));
    for (float x : m.cpu_bound) h.cpu_bound.push_back(static_cast<double>(x));
    for (const auto& t : m.tasks) {
      display::TaskRow r;
      r.process = t.process;
      r.task = t.task;
      r.policy = t.policy;
      r.cpu = t.cpu;
      r.priority = t.priority;
      r.periodic = t.periodic != 0;
      r.rt_granted = t.rt_granted != 0;
      r.alive = t.alive != 0;
      r.period_us = t.period_us;
      r.deadline_us = t.deadline_us;
      r.jobs = t.jobs;
      r.deadline_misses = t.deadline_misses;
      r.exec_p50_us = static_cast<double>(t.exec_p50_us);
      r.exec_p99_us = static_cast<double>(t.exec_p99_us);
      r.exec_max_us = static_cast<double>(t.exec_max_us);
      r.jitter_p50_us = static_cast<double>(t.jitter_p50_us);
      r.jitter_p99_us = static_cast<double>(t.jitter_p99_us);
      r.jitter_max_us = static_cast<double>(t.jitter_max_us);
      r.utilisation = static_cast<double>(t.utilisation);
      h.tasks.push_back(std::move(r));
    }
    h.events = m.events;
    snap.put(channels::kSchedStatus + std::string("/") + m.host, m);
    std::lock_guard<std::mutex> lock(sh.mutex);
    sh.state->on_sched(std::move(h));
  });
  bus.subscribe<arm_cmd_t>(channels::kArmCmd, [&](const arm_cmd_t& m) {
    snap.put(channels::kArmCmd, m);
    std::lock_guard<std::mutex> lock(sh.mutex);
    sh.state->on_arm_command(m.header.sender, m.seq, m.source_frame_utime, m.header.utime);
  });
  bus.subscribe<arm_goal_t>(channels::kArmGoal,
                            [&](const arm_goal_t& m) { snap.put(channels::kArmGoal, m); });
  bus.subscribe<arm_ack_t>(channels::kArmAck,
                           [&](const arm_ack_t& m) { snap.put(channels::kArmAck, m); });
  bus.subscribe<motion_done_t>(channels::kMotionDone,
                               [&](const motion_done_t& m) { snap.put(channels::kMotionDone, m); });
  bus.subscribe<shepherd_display_box_t>(
      channels::kDisplayBox,
      [&](const shepherd_display_box_t& m) { snap.put(channels::kDisplayBox, m); });
}

void update_rates(Bus& bus, Shared& sh) {
  std::map<std::string, uint64_t> totals;
  for (const auto& c : heard_channels()) totals[c] = bus.counters(c).received;
  std::lock_guard<std::mutex> lock(sh.rates_mutex);
  sh.rates.add_sample(static_cast<double>(mono_ns()) / 1e9, totals);
}

std::map<std::string, double> current_rates(Shared& sh) {
  std::lock_guard<std::mutex> lock(sh.rates_mutex);
  return sh.rates.rates();
}

// Publishes the part of `c` that `target` names. Returns false on a send failure.
bool publish_control(Bus& bus, display::Target target, const Controls& c) {
  switch (target) {
    case display::Target::kVision: {
      shepherd_vision_cmd_t m{};
      m.utime = wall_us();
      m.paused = c.vision.paused;
      m.mode = static_cast<int8_t>(c.vision.mode);
      m.scan = static_cast<int8_t>(c.vision.scan);
      m.threshold = c.vision.threshold;
      return bus.publish(channels::kVisionCmd, m);
    }
    case display::Target::kSim: {
      shepherd_sim_cmd_t m{};
      m.utime = wall_us();
      m.sheep = c.sim.sheep;
      m.reset = false;
      m.seed = c.sim.seed;
      return bus.publish(channels::kSimCmd, m);
    }
    case display::Target::kPlanner: {
      shepherd_planner_cmd_t m{};
      m.utime = wall_us();
      m.planner = c.planner;
      return bus.publish(channels::kPlannerCmd, m);
    }
    case display::Target::kBox: {
      shepherd_display_box_t m{};
      m.utime = wall_us();
      m.visible = c.box.visible;
      m.u = static_cast<float>(c.box.u);
      m.v = static_cast<float>(c.box.v);
      m.half_size_px = static_cast<float>(c.box.half_size_px);
      return bus.publish(channels::kDisplayBox, m);
    }
    case display::Target::kEstop: {
      estop_t m{};
      m.utime = wall_us();
      m.stop = c.estop;
      m.reason = c.estop ? "operator pressed STOP on the display page"
                         : "operator pressed release on the display page";
      return bus.publish(channels::kEstop, m);
    }
    case display::Target::kNone:
      break;
  }
  return false;
}

void set_json(httplib::Response& res, const nlohmann::json& j, int status = 200) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(j.dump(), "application/json");
}

void add_routes(httplib::Server& svr, Bus& bus, Shared& sh, Snapshot& snap, int max_fps) {
  svr.Get(R"(/|/index\.html|/display\.js|/display\.css)",
          [](const httplib::Request& req, httplib::Response& res) {
            const auto* a = display::find_web_asset(req.path == "/" ? "/index.html" : req.path);
            if (a == nullptr) {
              res.status = 404;
              return;
            }
            res.set_content(reinterpret_cast<const char*>(a->data), a->size, a->content_type);
          });

  svr.Get("/api/state", [&](const httplib::Request&, httplib::Response& res) {
    sh.last_request_mono_ns = mono_ns();
    auto rates = current_rates(sh);
    std::lock_guard<std::mutex> lock(sh.mutex);
    sh.state->set_rates(std::move(rates));
    set_json(res, sh.state->to_json(sh.controls, wall_us()));
  });

  svr.Get("/api/rates", [&](const httplib::Request&, httplib::Response& res) {
    set_json(res, current_rates(sh));
  });

  const int64_t min_gap_ns = 1'000'000'000 / max_fps;
  svr.Get("/api/frame.jpg", [&, min_gap_ns](const httplib::Request&, httplib::Response& res) {
    sh.last_request_mono_ns = mono_ns();
    std::shared_ptr<const camera_frame_t> frame;
    {
      std::lock_guard<std::mutex> lock(sh.mutex);
      frame = sh.frame;
    }
    std::lock_guard<std::mutex> lock(sh.jpeg_mutex);
    const int64_t now = mono_ns();
    // Encode only a newer frame, and at most max_fps times a second on
    // average. A token bucket rather than a minimum gap: polls at 20 Hz
    // against a 66 ms gap would encode only every other poll (10 images/s).
    sh.jpeg_tokens = std::min(2.0, sh.jpeg_tokens + static_cast<double>(now - sh.jpeg_mono_ns) /
                                                        static_cast<double>(min_gap_ns));
    sh.jpeg_mono_ns = now;
    if (frame && frame->frame_index != sh.jpeg_frame_index && sh.jpeg_tokens >= 1.0) {
      try {
        const auto& bytes =
            sh.encoder.encode(frame->data.data(), static_cast<int64_t>(frame->data.size()),
                              frame->width, frame->height);
        sh.jpeg.assign(reinterpret_cast<const char*>(bytes.data()), bytes.size());
        sh.jpeg_frame_index = frame->frame_index;
        sh.jpeg_tokens -= 1.0;
        ++sh.jpegs_encoded;
      } catch (const std::exception& e) {
        spdlog::warn("camera frame {} not shown: {}", frame->frame_index, e.what());
      }
    }
    if (sh.jpeg.empty()) {
      res.status = 204;  // no frame yet
      return;
    }
    res.set_header("Cache-Control", "no-store");
    res.set_header("X-Frame-Index", std::to_string(sh.jpeg_frame_index));
    res.set_content(sh.jpeg, "image/jpeg");
  });

  svr.Post("/api/cmd", [&](const httplib::Request& req, httplib::Response& res) {
    std::map<std::string, std::string> params;
    std::string command;
    for (const auto& [k, v] : req.params) {
      if (params.count(k) != 0 || (k == "cmd" && !command.empty())) {
        set_json(res, {{"error", "parameter '" + k + "' given twice"}}, 400);
        return;
      }
      if (k == "cmd") {
        command = v;
      } else {
        params[k] = v;
      }
    }
    if (command.empty()) {
      set_json(res, {{"error", "missing parameter 'cmd'"}}, 400);
      return;
    }
    std::lock_guard<std::mutex> lock(sh.mutex);
    const display::CommandValidator validator(sh.frame ? sh.frame->width : 512,
                                              sh.frame ? sh.frame->height : 482);
    const auto r = validator.validate(command, params, sh.controls);
    if (!r.ok) {
      spdlog::warn("refused display request '{}': {}", command, r.reason);
      set_json(res, {{"error", r.reason}}, 400);
      return;
    }
    if (!publish_control(bus, r.target, r.controls)) {
      set_json(res, {{"error", "could not publish the command on LCM"}}, 500);
      return;
    }
    sh.controls = r.controls;
    spdlog::info("display request '{}' sent", command);
    set_json(res, {{"ok", true}});
  });

  svr.Get("/api/debug", [&](const httplib::Request&, httplib::Response& res) {
    nlohmann::json j;
    j["utime"] = wall_us();
    j["rates_hz"] = current_rates(sh);
    j["channels"] = snap.to_json();
    {
      std::lock_guard<std::mutex> lock(sh.mutex);
      j["display"] = sh.state->to_json(sh.controls, wall_us());
    }
    for (const auto& c : heard_channels()) {
      const auto k = bus.counters(c);
      j["counters"][c] = {{"received", k.received},
                          {"decode_errors", k.decode_errors},
                          {"handler_errors", k.handler_errors}};
    }
    res.set_header("Content-Disposition", "attachment; filename=\"ephor-debug.json\"");
    set_json(res, j);
  });
}

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{"ephor-display: live web page for watching and steering the system"};
  ProcessArgs args;
  add_process_flags(app, args, "display");
  std::string address = "127.0.0.1";
  int port = 8080;
  std::string calibration_path;
  int max_fps = 15;
  display::DisplayOptions options;
  app.add_option("--http-address", address, "address to serve the page on (default loopback)");
  app.add_option("--http-port", port, "TCP port of the page (default 8080)")
      ->check(CLI::Range(1, 65535));
  app.add_option("--calibration", calibration_path,
                 "image-to-field calibration (Protobuf text); default "
                 "deploy/calibration/sim.pbtxt in the repository");
  app.add_option("--max-fps", max_fps, "camera images per second at most (default 15)")
      ->check(CLI::Range(1, 30));
  app.add_option("--path-horizon-s", options.path_horizon_s,
                 "predicted paths: velocity x this, s (default 3)")
      ->check(CLI::Range(0.0, 30.0));
  app.add_option("--tool-radius-mm", options.tool_radius_mm,
                 "footprint of the manipulator tip drawn on the table, mm (default 40)")
      ->check(CLI::Range(1.0, 500.0));
  int sim_seed = 1;
  app.add_option(
      "--sim-seed", sim_seed,
      "the simulator's seed, sent back unchanged in shepherd_sim_cmd_t (full state) until a "
      "SIM_CMD names another (default 1, ephor-sim's default)");
  CLI11_PARSE(app, argc, argv);
  init_logging(args.name);

  try {
    if (calibration_path.empty()) {
      calibration_path = (repo_dir() / "deploy" / "calibration" / "sim.pbtxt").string();
    }
    const auto calibration = calibration::FieldCalibration::load(calibration_path);
    const geometry::Workcell workcell;
    display::OverlayGeometry geometry(calibration.matrix_at_height(0.0), workcell.field_length_mm,
                                      workcell.field_width_mm);

    Bus bus(args.lcm_url, args.name);
    Shared sh;
    sh.controls.sim.seed = sim_seed;
    sh.state = std::make_unique<display::DisplayState>(geometry, options);
    Snapshot snap;
    subscribe_all(bus, sh, snap);

    httplib::Server svr;
    add_routes(svr, bus, sh, snap, max_fps);
    if (!svr.bind_to_port(address.c_str(), port)) {
      throw std::runtime_error("cannot listen on http://" + address + ":" + std::to_string(port) +
                               " (address in use or not available?)");
    }
    bus.start();
    std::thread http([&svr] { svr.listen_after_bind(); });
    spdlog::info("display page at http://{}:{}/ (calibration {})", address, port, calibration_path);

    // Rate samples every 250 ms; a status line every 10 s.
    int ticks = 0;
    uint64_t jpegs_at_status = 0;
    while (wait_for_shutdown_signal(0.25) == 0) {
      update_rates(bus, sh);
      // A pressed STOP is repeated every second, so a lost message or an
      // ephor-arm started later still hears it. A release is sent once: a
      // repeated release would undo someone else's stop.
      if (ticks % 4 == 0) {
        std::lock_guard<std::mutex> lock(sh.mutex);
        if (sh.controls.estop) publish_control(bus, display::Target::kEstop, sh.controls);
      }
      if (++ticks % 40 == 0) {
        uint64_t jpegs = 0;
        {
          std::lock_guard<std::mutex> lock(sh.jpeg_mutex);
          jpegs = sh.jpegs_encoded;
        }
        const bool watched = mono_ns() - sh.last_request_mono_ns.load() < 2'000'000'000;
        spdlog::info("{}; {:.1f} images/s encoded over the last 10 s",
                     watched ? "watched" : "nobody watching",
                     static_cast<double>(jpegs - jpegs_at_status) / 10.0);
        jpegs_at_status = jpegs;
      }
    }
    svr.stop();
    http.join();
    bus.stop();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
