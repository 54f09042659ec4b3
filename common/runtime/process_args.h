#pragma once
// Flags every ephor process accepts, and a clean shutdown on SIGINT/SIGTERM.
// The launcher passes them as environment variables too (EPHOR_PROCESS,
// EPHOR_HOST, LCM_DEFAULT_URL), so flags are only needed by hand.

#include <iostream>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace ephor {

struct ProcessArgs {
  std::string name;     // process name (sender name, task-table key)
  std::string host;     // host name the process belongs to
  std::string lcm_url;  // "" = LCM_DEFAULT_URL or the default
  bool no_mlock = false;
};

// Adds --name, --host, --lcm-url and --no-mlock with defaults taken from the
// environment (EPHOR_PROCESS, EPHOR_HOST or the machine's hostname).
void add_process_flags(CLI::App& app, ProcessArgs& args, const std::string& default_name);

// Parses the command line (issue 18: bad input at the edges a person
// touches). Returns nothing when the process should go on, else the status
// main() returns: 0 after --help, 2 after a bad flag (an unknown flag, a flag
// without its value, a number out of range), reported as one line on stderr
// that names it. Header-only so that tools without ephor_common use it too.
inline std::optional<int> parse_flags(CLI::App& app, int argc, const char* const* argv) {
  try {
    app.parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    std::string name = argc > 0 ? std::string(argv[0]) : std::string("ephor");
    name = name.substr(name.find_last_of('/') + 1);
    std::cerr << name << ": " << e.what() << "\n";
    return 2;
  }
}

// Blocks SIGINT and SIGTERM in the calling thread and every thread it starts
// afterwards. Call first thing in main(), before any thread exists.
void block_shutdown_signals();
// Waits until SIGINT or SIGTERM arrives (after block_shutdown_signals()), or
// until `timeout_s` seconds have passed when it is > 0. Returns the signal
// number, or 0 on timeout.
int wait_for_shutdown_signal(double timeout_s = 0.0);

}  // namespace ephor
