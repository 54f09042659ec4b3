#pragma once
// DisplayServer: what every system's live web page has in common, written
// once. A system's display process is its own state builder (a pure library
// turning its messages into the JSON its page draws), its own web files and
// a thin main that wires the two through this class:
//
//   GET  /, /<file>       the page's embedded files (display_page.cmake)
//   GET  /api/state       the system's JSON, plus "sched" (the scheduler's
//                         task table from EPHOR_SCHED_STATUS), "rates_hz"
//                         (messages/s per channel heard) and, for a system
//                         with an arm, "controls": {"estop": held}
//   GET  /api/frame.jpg   the newest camera frame as JPEG (204 without one)
//   POST /api/cmd?cmd=C&… "estop" (systems with an arm) or the system's own
//                         commands; HTTP 400 with {"error": reason} when refused
//   GET  /api/debug       the newest message of every channel heard (JSON download)
//   GET  /api/rates       messages per second per channel (JSON)
//
// The page polls state and frame: each answer is the newest data (no queue
// to fall behind on), a slow browser gets fewer updates, and no server
// thread is held per client. Frames are JPEG-encoded only when asked for and
// newer, at most max_fps times a second on average.
//
// Threading: message handlers run on the Bus's thread, state builders and
// command handlers on httplib's threads; all of them are called with one
// lock held (the server's), so a system's state needs no locking of its own.

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/display/estop_control.h"
#include "common/display/frame_encoder.h"
#include "common/display/newest_messages.h"
#include "common/display/rate_meter.h"
#include "common/display/sched_table.h"
#include "common/display/web_assets.h"
#include "common/lcm/bus.h"
#include "ephor/camera_frame_t.hpp"

namespace ephor::display {

struct DisplayServerOptions {
  std::string http_address = "127.0.0.1";  // loopback: the page is for this machine's user
  int http_port = 8080;
  // Channel of camera_frame_t served as /api/frame.jpg; empty = no camera.
  std::string camera_channel;
  int max_fps = 15;  // camera images encoded per second at most (1..30)
  // The system has an arm: the page's STOP / release (cmd=estop) publishes
  // ESTOP (estop_t), a held stop again every second.
  bool estop = false;
};

// A command's outcome: ok, or refused with the reason (HTTP 400).
struct CommandReply {
  bool ok = false;
  std::string error;
  int http_status = 400;  // when refused: 400 bad request, 500 could not send
  static CommandReply sent() { return {true, "", 200}; }
  static CommandReply refused(std::string why, int status = 400) {
    return {false, std::move(why), status};
  }
};

class DisplayServer {
 public:
  using AssetLookup = const WebAsset* (*)(std::string_view path);
  // The system's part of /api/state; now_us = wall clock (us).
  using StateBuilder = std::function<nlohmann::json(int64_t now_us)>;
  // One command (not "estop"), its parameters without "cmd".
  using CommandHandler = std::function<CommandReply(
      const std::string& command, const std::map<std::string, std::string>& params)>;
  // Each camera frame (after the server kept it for /api/frame.jpg).
  using FrameHook = std::function<void(const camera_frame_t& frame, int64_t now_us)>;

  // `bus` must outlive the server; it is started by run(). `assets` finds
  // the page's embedded files.
  DisplayServer(Bus& bus, DisplayServerOptions options, AssetLookup assets);
  ~DisplayServer();
  DisplayServer(const DisplayServer&) = delete;
  DisplayServer& operator=(const DisplayServer&) = delete;

  // Subscribes `handler` to `channel`: the message is kept for the debug
  // dump and counted for the rates, then handed over with the lock held.
  // Call before run(). T needs a to_json() (lcm_json.h or the page's own).
  template <class T>
  void subscribe(const std::string& channel, std::function<void(const T&)> handler) {
    channels_.push_back(channel);
    bus_.subscribe<T>(channel, [this, channel, handler = std::move(handler)](const T& m) {
      newest_.put(channel, m);
      std::lock_guard<std::mutex> lock(mutex_);
      if (handler) handler(m);
    });
  }

  void set_state_builder(StateBuilder builder) { state_builder_ = std::move(builder); }
  void set_command_handler(CommandHandler handler) { command_handler_ = std::move(handler); }
  void set_frame_hook(FrameHook hook) { frame_hook_ = std::move(hook); }
  // GET `path` (e.g. "/api/scan") answers `builder`'s JSON, built with the
  // lock held: for data a page fetches less often than its state. Call
  // before run().
  void add_json_route(const std::string& path, StateBuilder builder);

  // The page's STOP is held. Call with the lock held (from a builder or handler).
  bool estop_held() const { return estop_.held(); }

  // The whole /api/state as the page gets it (takes the lock).
  nlohmann::json state_json();

  // Listens on the HTTP port (throws std::runtime_error naming the address
  // when it cannot), starts the bus, then serves until SIGINT or SIGTERM
  // (block_shutdown_signals() first); a status line every 10 s.
  void run(const std::string& page_name);

 private:
  struct Http;  // httplib's server, kept out of this header

  void subscribe_camera();
  void subscribe_sched();
  void add_routes();
  void update_rates();
  std::map<std::string, double> current_rates();
  bool publish_estop(bool stop);

  Bus& bus_;
  DisplayServerOptions options_;
  AssetLookup assets_;
  std::unique_ptr<Http> http_;
  std::vector<std::string> channels_;  // every channel subscribed, for rates and counters
  NewestMessages newest_;

  std::mutex mutex_;  // guards everything below it and the system's state
  StateBuilder state_builder_;
  CommandHandler command_handler_;
  FrameHook frame_hook_;
  SchedTable sched_;
  EstopControl estop_;
  std::shared_ptr<const camera_frame_t> frame_;

  std::mutex jpeg_mutex_;  // guards the encoder and the cached JPEG
  FrameEncoder encoder_{75};
  std::string jpeg_;
  int64_t jpeg_frame_index_ = -1;
  int64_t jpeg_mono_ns_ = 0;
  double jpeg_tokens_ = 2.0;  // token bucket: max_fps encodes/s on average, bursts of 2
  uint64_t jpegs_encoded_ = 0;
  std::atomic<int64_t> last_request_mono_ns_{0};

  std::mutex rates_mutex_;
  RateMeter rates_{2.0};
};

}  // namespace ephor::display
