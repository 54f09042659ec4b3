#include "common/runtime/process_args.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace ephor {
namespace {

std::string env_or(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return (v != nullptr && *v != '\0') ? std::string(v) : fallback;
}

std::string hostname() {
  char buf[256] = {};
  if (gethostname(buf, sizeof buf - 1) != 0) return "local";
  return buf;
}

sigset_t shutdown_set() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}

}  // namespace

void add_process_flags(CLI::App& app, ProcessArgs& args, const std::string& default_name) {
  args.name = env_or("EPHOR_PROCESS", default_name);
  args.host = env_or("EPHOR_HOST", hostname());
  app.add_option("--name", args.name, "process name (sender name; task-table key)")
      ->capture_default_str();
  app.add_option("--host", args.host, "host name this process belongs to")->capture_default_str();
  app.add_option("--lcm-url", args.lcm_url,
                 "LCM URL (default: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0)");
  app.add_flag("--no-mlock", args.no_mlock, "do not lock memory with mlockall");
}

void block_shutdown_signals() {
  const sigset_t set = shutdown_set();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
}

int wait_for_shutdown_signal(double timeout_s) {
  const sigset_t set = shutdown_set();
  if (timeout_s <= 0.0) {
    int sig = 0;
    while (sigwait(&set, &sig) != 0) {
    }
    return sig;
  }
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(timeout_s);
  ts.tv_nsec = static_cast<long>((timeout_s - std::floor(timeout_s)) * 1e9);
  while (true) {
    const int sig = sigtimedwait(&set, nullptr, &ts);
    if (sig > 0) return sig;
    if (errno == EAGAIN) return 0;
  }
}

}  // namespace ephor
