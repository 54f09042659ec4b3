#include "common/display/display_server.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <spdlog/spdlog.h>

#include "common/display/json_format.h"
#include "common/display/lcm_json.h"
#include "common/display/sched_status_rows.h"
#include "common/lcm/channels.h"
#include "common/log/json_text.h"
#include "common/runtime/channels.h"
#include "common/runtime/process_args.h"
#include "common/time/clock.h"
#include "ephor/estop_t.hpp"
#include "ephor/sched_status_t.hpp"

// Last: httplib.h pulls in <resolv.h>, whose `_res` macro breaks Eigen headers included after it.
#include <httplib.h>

namespace ephor::display {

struct DisplayServer::Http {
  httplib::Server server;
};

namespace {

void set_json(httplib::Response& res, const nlohmann::json& j, int status = 200) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(json_text(j), "application/json");  // any bytes from the bus: U+FFFD
}

}  // namespace

DisplayServer::DisplayServer(Bus& bus, DisplayServerOptions options, AssetLookup assets)
    : bus_(bus), options_(std::move(options)), assets_(assets), http_(std::make_unique<Http>()) {
  if (options_.max_fps < 1 || options_.max_fps > 30) {
    throw std::invalid_argument("max_fps " + std::to_string(options_.max_fps) +
                                " is outside 1..30 images per second");
  }
  if (!options_.camera_channel.empty()) subscribe_camera();
  subscribe_sched();
  add_routes();
}

DisplayServer::~DisplayServer() = default;

void DisplayServer::subscribe_camera() {
  const std::string channel = options_.camera_channel;
  channels_.push_back(channel);
  bus_.subscribe<camera_frame_t>(channel, [this, channel](const camera_frame_t& m) {
    auto frame = std::make_shared<const camera_frame_t>(m);
    newest_.put(channel, frame_fields(m));
    std::lock_guard<std::mutex> lock(mutex_);
    frame_ = frame;
    if (frame_hook_) frame_hook_(m, wall_us());
  });
}

void DisplayServer::subscribe_sched() {
  channels_.push_back(channels::kSchedStatus);
  bus_.subscribe<sched_status_t>(channels::kSchedStatus, [this](const sched_status_t& m) {
    newest_.put(channels::kSchedStatus + std::string("/") + m.host, m);
    auto h = host_sched_of(m);
    std::lock_guard<std::mutex> lock(mutex_);
    sched_.on_sched(std::move(h));
  });
}

void DisplayServer::update_rates() {
  std::map<std::string, uint64_t> totals;
  for (const auto& c : channels_) totals[c] = bus_.counters(c).received;
  std::lock_guard<std::mutex> lock(rates_mutex_);
  rates_.add_sample(static_cast<double>(mono_ns()) / 1e9, totals);
}

std::map<std::string, double> DisplayServer::current_rates() {
  std::lock_guard<std::mutex> lock(rates_mutex_);
  return rates_.rates();
}

bool DisplayServer::publish_estop(bool stop) {
  estop_t m{};
  m.utime = wall_us();
  m.stop = stop;
  m.reason = EstopControl::reason(stop);
  return bus_.publish(channels::kEstop, m);
}

nlohmann::json DisplayServer::state_json() {
  const auto rates = current_rates();
  std::lock_guard<std::mutex> lock(mutex_);
  const int64_t now = wall_us();
  nlohmann::json j = state_builder_ ? state_builder_(now) : nlohmann::json::object();
  if (!j.is_object()) j = nlohmann::json::object();
  j["utime"] = now;
  j["sched"] = sched_.to_json();
  nlohmann::json r = nlohmann::json::object();
  for (const auto& [channel, hz] : rates) r[channel] = r1(hz);
  j["rates_hz"] = r;
  if (options_.estop) j["controls"]["estop"] = estop_.held();
  return j;
}

void DisplayServer::add_routes() {
  auto& svr = http_->server;
  svr.Get(R"(/[A-Za-z0-9_.\-]*)", [this](const httplib::Request& req, httplib::Response& res) {
    const auto* a = assets_ ? assets_(req.path == "/" ? "/index.html" : req.path) : nullptr;
    if (a == nullptr) {
      res.status = 404;
      return;
    }
    res.set_content(reinterpret_cast<const char*>(a->data), a->size, a->content_type);
  });

  // Pages with a 3-D view (stripe's cloud, RAMBO's target) load three.js from Debian's libjs-three
  // (tools/ephor installs it), read once on the first request rather than embedded in every binary.
  svr.Get("/lib/three.min.js", [](const httplib::Request&, httplib::Response& res) {
    static const std::string kThreeJs = [] {
      std::ifstream in("/usr/share/javascript/three/three.min.js", std::ios::binary);
      std::ostringstream text;
      text << in.rdbuf();
      return text.str();
    }();
    if (kThreeJs.empty()) {
      res.status = 404;
      res.set_content("three.js not installed: apt-get install libjs-three", "text/plain");
      return;
    }
    res.set_content(kThreeJs, "application/javascript");
  });

  svr.Get("/api/state", [this](const httplib::Request&, httplib::Response& res) {
    last_request_mono_ns_ = mono_ns();
    set_json(res, state_json());
  });

  svr.Get("/api/rates", [this](const httplib::Request&, httplib::Response& res) {
    set_json(res, current_rates());
  });

  const int64_t min_gap_ns = 1'000'000'000 / options_.max_fps;
  svr.Get("/api/frame.jpg", [this, min_gap_ns](const httplib::Request&, httplib::Response& res) {
    last_request_mono_ns_ = mono_ns();
    std::shared_ptr<const camera_frame_t> frame;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      frame = frame_;
    }
    std::lock_guard<std::mutex> lock(jpeg_mutex_);
    const int64_t now = mono_ns();
    // Encode only a newer frame, and at most max_fps times a second on
    // average. A token bucket rather than a minimum gap: polls at 20 Hz
    // against a 66 ms gap would encode only every other poll (10 images/s).
    jpeg_tokens_ = std::min(2.0, jpeg_tokens_ + static_cast<double>(now - jpeg_mono_ns_) /
                                                    static_cast<double>(min_gap_ns));
    jpeg_mono_ns_ = now;
    if (frame && frame->frame_index != jpeg_frame_index_ && jpeg_tokens_ >= 1.0) {
      try {
        const auto& bytes =
            encoder_.encode(frame->data.data(), static_cast<int64_t>(frame->data.size()),
                            frame->width, frame->height);
        jpeg_.assign(reinterpret_cast<const char*>(bytes.data()), bytes.size());
        jpeg_frame_index_ = frame->frame_index;
        jpeg_tokens_ -= 1.0;
        ++jpegs_encoded_;
      } catch (const std::exception& e) {
        spdlog::warn("camera frame {} not shown: {}", frame->frame_index, e.what());
      }
    }
    if (jpeg_.empty()) {
      res.status = 204;  // no frame yet (or no camera)
      return;
    }
    res.set_header("Cache-Control", "no-store");
    res.set_header("X-Frame-Index", std::to_string(jpeg_frame_index_));
    res.set_content(jpeg_, "image/jpeg");
  });

  svr.Post("/api/cmd", [this](const httplib::Request& req, httplib::Response& res) {
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
    std::lock_guard<std::mutex> lock(mutex_);
    CommandReply reply;
    if (options_.estop && command == "estop") {
      const auto it = params.find("value");
      std::string why;
      const auto stop = EstopControl::parse(
          it == params.end() ? std::nullopt : std::optional<std::string>(it->second), why);
      if (!stop) {
        reply = CommandReply::refused(why);
      } else if (!publish_estop(*stop)) {
        reply = CommandReply::refused("could not publish the command on LCM", 500);
      } else {
        estop_.set_held(*stop);
        reply = CommandReply::sent();
      }
    } else if (command_handler_) {
      reply = command_handler_(command, params);
    } else {
      reply = CommandReply::refused(
          "unknown command '" + command + "' (" +
          (options_.estop ? "this page has only estop" : "this page has no commands") + ")");
    }
    if (!reply.ok) {
      if (reply.http_status == 400)
        spdlog::warn("refused display request '{}': {}", command, reply.error);
      set_json(res, {{"error", reply.error}}, reply.http_status);
      return;
    }
    spdlog::info("display request '{}' sent", command);
    set_json(res, {{"ok", true}});
  });

  svr.Get("/api/debug", [this](const httplib::Request&, httplib::Response& res) {
    nlohmann::json j;
    j["utime"] = wall_us();
    j["rates_hz"] = current_rates();
    j["channels"] = newest_.to_json();
    j["display"] = state_json();
    for (const auto& c : channels_) {
      const auto k = bus_.counters(c);
      j["counters"][c] = {{"received", k.received},
                          {"decode_errors", k.decode_errors},
                          {"handler_errors", k.handler_errors}};
    }
    res.set_header("Content-Disposition", "attachment; filename=\"ephor-debug.json\"");
    set_json(res, j);
  });
}

void DisplayServer::add_json_route(const std::string& path, StateBuilder builder) {
  http_->server.Get(
      path, [this, builder = std::move(builder)](const httplib::Request&, httplib::Response& res) {
        last_request_mono_ns_ = mono_ns();
        nlohmann::json j;
        {
          std::lock_guard<std::mutex> lock(mutex_);
          j = builder(wall_us());
        }
        set_json(res, j);
      });
}

void DisplayServer::run(const std::string& page_name) {
  auto& svr = http_->server;
  if (!svr.bind_to_port(options_.http_address.c_str(), options_.http_port)) {
    throw std::runtime_error("cannot listen on http://" + options_.http_address + ":" +
                             std::to_string(options_.http_port) +
                             " (address in use or not available?)");
  }
  bus_.start();
  std::thread http([&svr] { svr.listen_after_bind(); });
  spdlog::info("{} page at http://{}:{}/", page_name, options_.http_address, options_.http_port);

  // Rate samples every 250 ms; a status line every 10 s.
  int ticks = 0;
  uint64_t jpegs_at_status = 0;
  while (wait_for_shutdown_signal(0.25) == 0) {
    update_rates();
    // A pressed STOP is repeated every second, so a lost message or an
    // ephor-arm started later still hears it. A release is sent once: a
    // repeated release would undo someone else's stop.
    if (ticks % 4 == 0) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (options_.estop && estop_.held()) publish_estop(true);
    }
    if (++ticks % 40 == 0) {
      uint64_t jpegs = 0;
      {
        std::lock_guard<std::mutex> lock(jpeg_mutex_);
        jpegs = jpegs_encoded_;
      }
      const bool watched = mono_ns() - last_request_mono_ns_.load() < 2'000'000'000;
      if (options_.camera_channel.empty()) {
        spdlog::info("{}", watched ? "watched" : "nobody watching");
      } else {
        spdlog::info("{}; {:.1f} images/s encoded over the last 10 s",
                     watched ? "watched" : "nobody watching",
                     static_cast<double>(jpegs - jpegs_at_status) / 10.0);
      }
      jpegs_at_status = jpegs;
    }
  }
  svr.stop();
  http.join();
  bus_.stop();
}

}  // namespace ephor::display
