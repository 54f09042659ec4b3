#pragma once
// ProcessGroup: starts child processes, captures their output line by line,
// notices when they exit, and stops them (SIGTERM, then SIGKILL after a grace
// time). No LCM: procs/shared/deputy's DeputyCore drives it, for ephor-deputy and
// ephor-launch alike.
//
// Children run in their own process group (a terminal's Ctrl-C reaches only
// the launcher, which then stops them in reverse start order) and get
// SIGTERM if the launcher dies (PR_SET_PDEATHSIG).

#include <sys/types.h>

#include <chrono>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace ephor::launcher {

struct ProcessSpec {
  std::string name;                                      // shown as the output prefix
  std::string path;                                      // executable
  std::vector<std::string> args;                         // argv[1..]
  std::vector<std::pair<std::string, std::string>> env;  // added to the launcher's environment
  bool allow_exit = false;                               // exit status 0 is not a failure
};

struct ExitInfo {
  std::string name;
  pid_t pid = 0;
  bool signaled = false;  // killed by a signal (code = signal number)
  int code = 0;           // exit status or signal number
  bool failure = false;   // not an allowed exit (non-zero, signal, or 0 without allow_exit)
  std::string describe()
      const;  // e.g. "exited with status 3", "killed by signal 11 (Segmentation fault)"
};

class ProcessGroup {
 public:
  // `on_line` gets each complete output line (stdout and stderr merged) of
  // each child, without the newline.
  using LineHandler = std::function<void(const std::string& name, const std::string& line)>;
  explicit ProcessGroup(LineHandler on_line);
  ~ProcessGroup();
  ProcessGroup(const ProcessGroup&) = delete;
  ProcessGroup& operator=(const ProcessGroup&) = delete;

  // Starts a child. Throws std::runtime_error naming the process and the
  // reason when it cannot be started (e.g. the executable does not exist).
  pid_t start(const ProcessSpec& spec);

  // Forwards output and reaps children for up to `timeout_ms`; returns the
  // children that exited meanwhile.
  std::vector<ExitInfo> poll(int timeout_ms);

  // Sends SIGTERM to every running child (newest first), waits up to `grace`
  // for them, then SIGKILLs the rest. Output is forwarded meanwhile.
  std::vector<ExitInfo> stop_all(std::chrono::milliseconds grace);

  // Sends `sig` to the running child `pid` (the deputy stops one process at
  // a time). Returns false when `pid` is not a running child of this group.
  bool signal(pid_t pid, int sig);

  size_t running() const;

 private:
  struct Child {
    ProcessSpec spec;
    pid_t pid = 0;
    int out_fd = -1;
    std::string partial;
    bool exited = false;
  };
  void drain(Child& child, bool final);
  std::vector<ExitInfo> reap();

  LineHandler on_line_;
  std::vector<Child> children_;
};

// Resolves an executable name: a name with '/' is taken as a path; otherwise
// it is looked up in `bin_dir` first, then in $PATH. "" when not found.
std::string resolve_executable(const std::string& exec, const std::string& bin_dir);

}  // namespace ephor::launcher
