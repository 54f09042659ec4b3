// ephor-log: reads LCM logs (lcm-logger's format) with our types decoded.
//
//   ephor-log export FILE --channel REGEX [--csv | --json] [--bytes] [--out FILE]
//   ephor-log info FILE
//
// Types are read from lcmtypes/*.lcm at run time (--types DIR; default the
// repository's), so a log is decoded with the fields it was recorded with.
// Run through `tools/ephor log ...` (tools/ephor.d/log).

#include <fstream>
#include <iostream>

#include <CLI/CLI.hpp>

#include "common/runtime/process_args.h"
#include "tools/log/lcm_schema.h"
#include "tools/log/log_exporter.h"

namespace {

std::string default_types_dir() {
  if (const char* root = std::getenv("EPHOR_ROOT"); root != nullptr && *root != '\0')
    return std::string(root) + "/lcmtypes";
  return EPHOR_LCMTYPES_DIR;  // the source tree this binary was built from
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ephor-log: decode LCM logs of ephor's types"};
  app.require_subcommand(1);
  std::string types_dir = default_types_dir();
  app.add_option("--types", types_dir, "folder of the .lcm type definitions")
      ->capture_default_str();

  std::string log_path;
  std::string out_path;
  ephor::logtools::ExportOptions options;
  bool csv = false;
  bool json = false;
  auto* exp = app.add_subcommand("export", "write the messages of some channels as CSV or JSON");
  exp->add_option("file", log_path, "LCM log file")->required()->check(CLI::ExistingFile);
  exp->add_option("--channel", options.channel_regex,
                  "channel name or regular expression (POSIX extended, whole name)")
      ->required();
  exp->add_flag("--csv", csv, "CSV: a header row, one row per message (or per array element)");
  exp->add_flag("--json", json, "JSON lines, one object per message (default)");
  exp->add_flag("--bytes", options.include_bytes,
                "include byte arrays (camera pixels) in full (JSON only)");
  exp->add_option("--out", out_path, "write here instead of standard output");

  std::string info_path;
  auto* info = app.add_subcommand("info", "channels, types, rates and missing messages of a log");
  info->add_option("file", info_path, "LCM log file")->required()->check(CLI::ExistingFile);
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;

  try {
    const auto schema = ephor::logtools::LcmSchema::load_directory(types_dir);
    if (info->parsed()) {
      ephor::logtools::print_summary(ephor::logtools::summarize_log(schema, info_path), std::cout);
      return 0;
    }
    if (csv && json) {
      std::cerr << "ephor-log export: --csv and --json exclude each other\n";
      return 2;
    }
    options.format =
        csv ? ephor::logtools::ExportFormat::kCsv : ephor::logtools::ExportFormat::kJsonLines;
    std::ofstream file;
    if (!out_path.empty()) {
      file.open(out_path);
      if (!file) {
        std::cerr << "ephor-log export: cannot write " << out_path << "\n";
        return 1;
      }
    }
    std::ostream& out = out_path.empty() ? std::cout : file;
    const auto stats = ephor::logtools::LogExporter(schema, options).run(log_path, out);
    out.flush();
    for (const auto& e : stats.first_errors) std::cerr << "ephor-log export: skipped " << e << "\n";
    if (stats.undecodable > 0)
      std::cerr << "ephor-log export: " << stats.undecodable
                << " message(s) could not be decoded and were skipped\n";
    if (stats.exported == 0) {
      std::cerr << "ephor-log export: no message on a channel matching '" << options.channel_regex
                << "' in " << log_path << " (" << stats.events
                << " events; `tools/ephor log info FILE` lists the channels)\n";
      return 1;
    }
    if (!out_path.empty())
      std::cerr << "ephor-log export: " << stats.exported << " message(s), " << stats.rows
                << " row(s) -> " << out_path << "\n";
  } catch (const std::exception& e) {
    std::cerr << "ephor-log: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
