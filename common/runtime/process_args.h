#pragma once
// Flags every ephor process accepts, and a clean shutdown on SIGINT/SIGTERM.
// The launcher passes them as environment variables too (EPHOR_PROCESS,
// EPHOR_HOST, LCM_DEFAULT_URL), so flags are only needed by hand.

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

// Blocks SIGINT and SIGTERM in the calling thread and every thread it starts
// afterwards. Call first thing in main(), before any thread exists.
void block_shutdown_signals();
// Waits until SIGINT or SIGTERM arrives (after block_shutdown_signals()), or
// until `timeout_s` seconds have passed when it is > 0. Returns the signal
// number, or 0 on timeout.
int wait_for_shutdown_signal(double timeout_s = 0.0);

}  // namespace ephor
