// Fuzz target (issue 18): a recorded GROUND_TRUTH row (JSON, as `tools/ephor
// log export --json` writes it) read by ephor-bench-planner --start
// (sheep_from_ground_truth_row). Bad input must end in
// std::invalid_argument. Seeds: fuzz_corpus/shepherd_recorded_start.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "procs/shepherd/planner/recorded_start.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    (void)ephor::planner::sheep_from_ground_truth_row(
        std::string(reinterpret_cast<const char*>(data), size));
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
