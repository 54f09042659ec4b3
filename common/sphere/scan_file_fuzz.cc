// Fuzz target (issue 18): a recorded range scan (CSV) as `tools/ephor sphere
// locate` reads it (ScanFile::read), cut into windows as it does. Bad input
// must end in ScanFileError (or split_windows' std::invalid_argument for
// too many windows). Seeds: fuzz_corpus/sphere_scan.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>

#include "common/sphere/scan_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const auto lines = ephor::sphere::ScanFile::read(in, "fuzz.csv");
    (void)ephor::sphere::split_windows(lines, 0.5);
    std::ostringstream out;
    ephor::sphere::ScanFile::write(out, lines);
  } catch (const ephor::sphere::ScanFileError&) {
  } catch (const std::invalid_argument&) {  // split_windows: more than kMaxWindows
  }
  return 0;
}
