// Fuzz target (issue 18): the work cell file every system's arm, simulator
// and planner are given with --workcell (load_workcell_file). Bad input must
// end in ConfigError. Seeds: fuzz_corpus/workcell (deploy/*/workcell.pbtxt).
#include <cstddef>
#include <cstdint>

#include "common/config/text_proto.h"
#include "common/fuzz/fuzz_input.h"
#include "common/geometry/workcell_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static ephor::fuzz::FuzzInputFile file;
  try {
    (void)ephor::geometry::load_workcell_file(file.write(data, size));
  } catch (const ephor::ConfigError&) {
  }
  return 0;
}
