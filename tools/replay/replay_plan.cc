#include "tools/replay/replay_plan.h"

#include <algorithm>
#include <set>
#include <sstream>
#include <stdexcept>

#include "common/lcm/channels.h"
#include "ephor/shepherd_blobs_t.hpp"
#include "ephor/shepherd_objects_t.hpp"

namespace ephor::replay {
namespace {

template <class T>
std::vector<uint8_t> reencode(const std::string& channel, const void* data, int size,
                              void (*zero)(T&)) {
  T msg;
  if (msg.decode(data, 0, size) != size) {
    throw std::invalid_argument(channel + ": " + std::to_string(size) + " bytes do not decode as " +
                                T::getTypeName());
  }
  zero(msg);
  std::vector<uint8_t> out(static_cast<size_t>(msg.getEncodedSize()));
  msg.encode(out.data(), 0, static_cast<int>(out.size()));
  return out;
}

}  // namespace

bool ReplayPlan::is_input(const std::string& channel) const {
  return std::find(input_channels.begin(), input_channels.end(), channel) != input_channels.end();
}

bool ReplayPlan::is_output(const std::string& channel) const {
  return std::find(output_channels.begin(), output_channels.end(), channel) !=
         output_channels.end();
}

ReplayPlan make_replay_plan(const std::string& procs) {
  std::set<std::string> names;
  std::stringstream in(procs);
  std::string name;
  while (std::getline(in, name, ',')) {
    if (name.empty()) continue;
    if (name != "vision" && name != "worldmodel") {
      throw std::invalid_argument("--procs: '" + name +
                                  "' cannot be replayed (known: vision, worldmodel)");
    }
    if (!names.insert(name).second) throw std::invalid_argument("--procs: '" + name + "' twice");
  }
  if (names.empty())
    throw std::invalid_argument("--procs: no process named (e.g. vision,worldmodel)");
  ReplayPlan plan;
  if (names.count("vision") != 0) {
    plan.processes.push_back({"vision", "ephor-vision", {"--on-frame"}});
    plan.frame_channel = channels::kCamera;
    plan.input_channels = {channels::kCamera, channels::kVisionCmd};
    plan.output_channels.push_back(channels::kBlobs);
  }
  if (names.count("worldmodel") != 0) {
    plan.processes.push_back({"worldmodel", "ephor-worldmodel", {}});
    if (plan.frame_channel.empty()) {
      plan.frame_channel = channels::kBlobs;
      plan.input_channels = {channels::kBlobs};
    }
    plan.output_channels.push_back(channels::kObjects);
  }
  plan.final_channel = plan.output_channels.back();
  return plan;
}

std::optional<int64_t> message_utime(const void* data, int size) {
  if (data == nullptr || size < 16) return std::nullopt;
  const auto* p = static_cast<const uint8_t*>(data) + 8;
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  return static_cast<int64_t>(v);
}

std::vector<uint8_t> normalised_output(const std::string& channel, const void* data, int size) {
  if (channel == channels::kBlobs) {
    return reencode<shepherd_blobs_t>(
        channel, data, size, +[](shepherd_blobs_t& m) {
          m.header.utime = 0;
          m.processing_us = 0.0f;
        });
  }
  if (channel == channels::kObjects) {
    return reencode<shepherd_objects_t>(
        channel, data, size, +[](shepherd_objects_t& m) { m.header.utime = 0; });
  }
  const auto* p = static_cast<const uint8_t*>(data);
  return std::vector<uint8_t>(p, p + size);
}

}  // namespace ephor::replay
