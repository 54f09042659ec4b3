// Fuzz target (issue 18): the ball-catching camera file as the vision process
// and the offline tracker read it (--camera: load_camera_file), then their
// check of the frames' size against it. A camera the loader accepts must
// round-trip through camera_to_text(). Bad input must end in ConfigError.
// Seeds: fuzz_corpus/catch_camera (deploy/catch/camera.pbtxt).
#include <cstddef>
#include <cstdint>

#include "common/catch/camera_file.h"
#include "common/config/text_proto.h"
#include "common/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static ephor::fuzz::FuzzInputFile file;
  try {
    const auto camera = ephor::catching::load_camera_file(file.write(data, size));
    (void)ephor::catching::frame_size_problem(camera, "fuzz.pbtxt", 640, 480, "frames");
    try {
      (void)ephor::catching::parse_camera_text(ephor::catching::camera_to_text(camera, "fuzz"),
                                               "round-trip");
    } catch (const ephor::ConfigError& e) {
      ephor::fuzz::fail(std::string("an accepted camera does not round-trip: ") + e.what());
    }
  } catch (const ephor::ConfigError&) {
  }
  return 0;
}
