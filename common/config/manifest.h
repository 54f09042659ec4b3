#pragma once
// The deployment manifest (manifest.proto): loading, validation and defaults.

#include <map>
#include <string>
#include <vector>

#include "common/config/manifest.pb.h"

namespace ephor {

// Parses and validates `path`; fills defaults (LCM group/port/buffer,
// scheduler settings, host "local" when none is named, each process's host).
// Throws ConfigError naming the file, the line and the field.
config::Manifest load_manifest(const std::string& path);
// Same, from text (for tests); `name` stands for the file in messages.
config::Manifest parse_manifest(const std::string& text, const std::string& name);

// The LCM URL the manifest asks for, e.g.
// "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=16777216".
std::string manifest_lcm_url(const config::Manifest& manifest);

// `url` with its receive buffer set to at least `bytes` (the recv_buf_size
// option replaced or added): a recorder that must ride out a disk stall while
// camera frames keep coming wants more than the processes do.
std::string lcm_url_with_receive_buffer(const std::string& url, long long bytes);

// Host names in manifest order.
std::vector<std::string> manifest_hosts(const config::Manifest& manifest);

// The process's args with ${param} replaced from `values` (parameter name ->
// value); an arg that refers to an empty or missing parameter is dropped.
std::vector<std::string> expand_args(const config::Process& process,
                                     const std::map<std::string, std::string>& values);

// -1 for "auto" / "", else the CPU index (validated on load).
int task_cpu(const config::Task& task);

}  // namespace ephor
