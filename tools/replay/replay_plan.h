#pragma once
// ReplayPlan: what a deterministic replay (tools/ephor replay) feeds and
// waits for, given the processes under test. Each process reads and writes
// fixed channels (common/lcm/channels.h):
//   vision:     reads CAMERA (frames) and VISION_CMD (mode, full state); writes BLOBS
//   worldmodel: reads BLOBS (frames);                                   writes OBJECTS
// Chained processes feed each other: with vision and worldmodel the replay
// feeds CAMERA and VISION_CMD from the log, and BLOBS comes from the live
// vision, not from the log.
//
// Per logged frame (a message on frame_channel) the replay publishes it and
// waits for the message of the same utime on final_channel (every type here
// starts with the frame's capture utime) before the next one. No LCM here.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ephor::replay {

struct ReplayProcess {
  std::string name;  // "vision", "worldmodel"
  std::string exec;  // binary, e.g. "ephor-vision"
  // Flags that make it deterministic under replay (e.g. vision --on-frame).
  std::vector<std::string> replay_args;
};

struct ReplayPlan {
  std::vector<ReplayProcess> processes;      // in pipeline order
  std::string frame_channel;                 // logged frames fed one at a time
  std::vector<std::string> input_channels;   // everything fed from the log (frame_channel first)
  std::vector<std::string> output_channels;  // recorded, in pipeline order
  std::string final_channel;                 // waited for after each frame

  bool is_input(const std::string& channel) const;
  bool is_output(const std::string& channel) const;
};

// Plan for a comma-separated list of process names ("vision,worldmodel",
// any order). Throws std::invalid_argument naming an unknown or repeated
// process, an empty list, or processes that do not form one chain.
ReplayPlan make_replay_plan(const std::string& procs);

// The utime every ephor message starts with (int64 big-endian after LCM's
// 8-byte type fingerprint); nullopt when the message is too short.
std::optional<int64_t> message_utime(const void* data, int size);

// An output message with the fields that depend on when the replay ran (the
// sender's publish time header.utime, vision's processing_us) set to 0, so
// two replays of one log give identical bytes. Throws std::invalid_argument
// when the bytes do not decode as the channel's type; other channels are
// returned unchanged.
std::vector<uint8_t> normalised_output(const std::string& channel, const void* data, int size);

}  // namespace ephor::replay
