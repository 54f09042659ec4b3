// Fuzz target (issue 18): the light-stripe calibration file as the range
// process and the scan planner read it (--calibration FILE --robot-seed N:
// calibration_from_flags), then the arm model it carries. A file the loader
// accepts must round-trip through stripe_calibration_text(). Bad input must
// end in ConfigError. Seeds: fuzz_corpus/stripe_calibration.
#include <cstddef>
#include <cstdint>

#include "common/config/text_proto.h"
#include "common/fuzz/fuzz_input.h"
#include "common/stripe/calibration_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static ephor::fuzz::FuzzInputFile file;
  static ephor::fuzz::FuzzInputFile again;
  try {
    const auto c = ephor::stripe::load_stripe_calibration(file.write(data, size));
    (void)ephor::stripe::calibration_from_flags(file.path(), c.robot_seed);
    (void)c.arm_model();
    const std::string text = ephor::stripe::stripe_calibration_text(c);
    try {
      (void)ephor::stripe::load_stripe_calibration(
          again.write(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
    } catch (const ephor::ConfigError& e) {
      ephor::fuzz::fail(std::string("an accepted calibration does not round-trip: ") + e.what());
    }
  } catch (const ephor::ConfigError&) {
  }
  return 0;
}
