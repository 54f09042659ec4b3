// Fuzz target (issue 18): a recorded LCM log (lcm-logger's format) as
// `tools/ephor log export` (JSON Lines and CSV) and `log info` read it. The
// events are read by liblcm; the decoding, the CSV layout and the summary are
// ours. Bad input must end in ExportError (or a message counted as
// undecodable). Seeds: fuzz_corpus/lcm_log (small logs of a few messages).
#include <cstddef>
#include <cstdint>
#include <sstream>

#include "common/config/repo_paths.h"
#include "common/fuzz/fuzz_input.h"
#include "tools/log/lcm_schema.h"
#include "tools/log/log_exporter.h"

using ephor::logtools::ExportFormat;
using ephor::logtools::LogExporter;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const ephor::logtools::LcmSchema schema =
      ephor::logtools::LcmSchema::load_directory(ephor::resolve_repo_path("lcmtypes"));
  static ephor::fuzz::FuzzInputFile file;
  const std::string& path = file.write(data, size);
  for (const ExportFormat format : {ExportFormat::kJsonLines, ExportFormat::kCsv}) {
    try {
      std::ostringstream out;
      (void)LogExporter(schema, {".*", format, false}).run(path, out);
    } catch (const ephor::logtools::ExportError&) {
    }
  }
  try {
    std::ostringstream out;
    ephor::logtools::print_summary(ephor::logtools::summarize_log(schema, path), out);
  } catch (const ephor::logtools::ExportError&) {
  }
  return 0;
}
