// Fuzz target (issue 18): RAMBO's target model file as the simulator and the
// pose, predictor and planner processes read it (--model FILE --diodes 0:
// cell_from_flags, which loads, checks and builds the cell). Bad input must
// end in ConfigError. Seeds: fuzz_corpus/rambo_target_model
// (deploy/rambo/target.pbtxt).
#include <cstddef>
#include <cstdint>

#include "common/config/text_proto.h"
#include "common/fuzz/fuzz_input.h"
#include "common/rambo/target_model_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static ephor::fuzz::FuzzInputFile file;
  try {
    (void)ephor::rambo::cell_from_flags(file.write(data, size), 0);
  } catch (const ephor::ConfigError&) {
  }
  return 0;
}
