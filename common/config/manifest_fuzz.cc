// Fuzz target (issue 18): the deployment manifest as ephor-launch, the
// scheduler and the sheriff load it (parse and validate, then the LCM URL,
// the hosts and every process's arguments). Bad input must end in
// ConfigError, never a crash. Seeds: fuzz_corpus/manifest (deploy/*.pbtxt).
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

#include "common/config/manifest.h"
#include "common/config/text_proto.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const ephor::config::Manifest manifest = ephor::parse_manifest(text, "fuzz.pbtxt");
    (void)ephor::manifest_lcm_url(manifest);
    (void)ephor::lcm_url_with_receive_buffer(ephor::manifest_lcm_url(manifest), 64 << 20);
    (void)ephor::manifest_hosts(manifest);
    std::map<std::string, std::string> values;
    for (const auto& p : manifest.param()) values[p.name()] = "v";
    for (const auto& process : manifest.process()) {
      (void)ephor::expand_args(process, values);
      for (const auto& task : process.task()) (void)ephor::task_cpu(task);
    }
  } catch (const ephor::ConfigError&) {
  }
  return 0;
}
