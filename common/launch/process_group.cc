#include "common/launch/process_group.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "common/time/clock.h"

namespace ephor::launcher {
namespace {

bool is_executable(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && access(path.c_str(), X_OK) == 0;
}

}  // namespace

std::string ExitInfo::describe() const {
  if (signaled) return "killed by signal " + std::to_string(code) + " (" + strsignal(code) + ")";
  return "exited with status " + std::to_string(code);
}

std::string resolve_executable(const std::string& exec, const std::string& bin_dir) {
  if (exec.find('/') != std::string::npos) return is_executable(exec) ? exec : "";
  if (!bin_dir.empty() && is_executable(bin_dir + "/" + exec)) return bin_dir + "/" + exec;
  const char* path = std::getenv("PATH");
  std::stringstream ss(path != nullptr ? path : "");
  std::string dir;
  while (std::getline(ss, dir, ':'))
    if (!dir.empty() && is_executable(dir + "/" + exec)) return dir + "/" + exec;
  return "";
}

ProcessGroup::ProcessGroup(LineHandler on_line) : on_line_(std::move(on_line)) {}

ProcessGroup::~ProcessGroup() { stop_all(std::chrono::milliseconds(2000)); }

pid_t ProcessGroup::start(const ProcessSpec& spec) {
  int out[2];
  int status_pipe[2];  // CLOEXEC: closed by a successful exec, carries errno if exec fails
  if (pipe2(out, O_CLOEXEC) != 0 || pipe2(status_pipe, O_CLOEXEC) != 0)
    throw std::runtime_error("cannot start " + spec.name + ": pipe: " + std::strerror(errno));

  std::vector<std::string> argv_s = {spec.path};
  argv_s.insert(argv_s.end(), spec.args.begin(), spec.args.end());
  std::vector<char*> argv;
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);

  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0)
    throw std::runtime_error("cannot start " + spec.name + ": fork: " + std::strerror(errno));
  if (pid == 0) {
    // Child: only async-signal-safe work until exec.
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(127);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none,
                nullptr);  // the launcher blocks SIGINT/SIGTERM; children must not inherit that
    dup2(out[1], STDOUT_FILENO);
    dup2(out[1], STDERR_FILENO);
    for (const auto& [k, v] : spec.env) setenv(k.c_str(), v.c_str(), 1);
    execv(spec.path.c_str(), argv.data());
    const int err = errno;
    (void)!write(status_pipe[1], &err, sizeof err);
    _exit(127);
  }
  close(out[1]);
  close(status_pipe[1]);
  int child_errno = 0;
  ssize_t n;
  do {
    n = read(status_pipe[0], &child_errno, sizeof child_errno);
  } while (n < 0 && errno == EINTR);
  close(status_pipe[0]);
  if (n == sizeof child_errno) {
    waitpid(pid, nullptr, 0);
    close(out[0]);
    throw std::runtime_error("cannot start " + spec.name + " (" + spec.path +
                             "): " + std::strerror(child_errno));
  }
  fcntl(out[0], F_SETFL, fcntl(out[0], F_GETFL) | O_NONBLOCK);
  Child c;
  c.spec = spec;
  c.pid = pid;
  c.out_fd = out[0];
  children_.push_back(std::move(c));
  return pid;
}

void ProcessGroup::drain(Child& child, bool final) {
  if (child.out_fd < 0) return;
  char buf[4096];
  while (true) {
    const ssize_t n = read(child.out_fd, buf, sizeof buf);
    if (n > 0) {
      // A NUL byte in a child's output would reach the deputy's output
      // message, which LCM encodes only up to the NUL while its size counts
      // past it, so every receiver would drop the batch: shown as "\0".
      for (ssize_t i = 0; i < n; ++i) {
        if (buf[i] == '\0')
          child.partial.append("\\0");
        else
          child.partial.push_back(buf[i]);
      }
      size_t pos;
      while ((pos = child.partial.find('\n')) != std::string::npos) {
        on_line_(child.spec.name, child.partial.substr(0, pos));
        child.partial.erase(0, pos + 1);
      }
      continue;
    }
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR)) {  // EOF or error
      close(child.out_fd);
      child.out_fd = -1;
      final = true;
    }
    break;
  }
  if (final && !child.partial.empty()) {
    on_line_(child.spec.name, child.partial);
    child.partial.clear();
  }
}

std::vector<ExitInfo> ProcessGroup::reap() {
  std::vector<ExitInfo> exits;
  for (auto& c : children_) {
    if (c.exited) continue;
    int status = 0;
    const pid_t r = waitpid(c.pid, &status, WNOHANG);
    if (r != c.pid) continue;
    c.exited = true;
    drain(c, true);
    ExitInfo e;
    e.name = c.spec.name;
    e.pid = c.pid;
    e.signaled = WIFSIGNALED(status);
    e.code = e.signaled ? WTERMSIG(status) : WEXITSTATUS(status);
    e.failure = e.signaled || e.code != 0 || !c.spec.allow_exit;
    exits.push_back(e);
  }
  return exits;
}

std::vector<ExitInfo> ProcessGroup::poll(int timeout_ms) {
  std::vector<pollfd> fds;
  std::vector<Child*> owners;
  for (auto& c : children_) {
    if (c.out_fd >= 0) {
      fds.push_back({c.out_fd, POLLIN, 0});
      owners.push_back(&c);
    }
  }
  // Wake at least every 50 ms to reap children whose pipes stay open (a
  // grandchild may hold them).
  const int wait_ms = std::min(timeout_ms, 50);
  if (!fds.empty()) {
    if (::poll(fds.data(), fds.size(), wait_ms) > 0) {
      for (size_t i = 0; i < fds.size(); ++i)
        if (fds[i].revents != 0) drain(*owners[i], false);
    }
  } else if (wait_ms > 0) {
    usleep(static_cast<useconds_t>(wait_ms) * 1000);
  }
  auto exits = reap();
  // Forget children that exited and whose output is closed: a deputy
  // restarts processes for days.
  children_.erase(std::remove_if(children_.begin(), children_.end(),
                                 [](const Child& c) { return c.exited && c.out_fd < 0; }),
                  children_.end());
  return exits;
}

bool ProcessGroup::signal(pid_t pid, int sig) {
  for (const auto& c : children_)
    if (c.pid == pid && !c.exited) return kill(pid, sig) == 0;
  return false;
}

std::vector<ExitInfo> ProcessGroup::stop_all(std::chrono::milliseconds grace) {
  std::vector<ExitInfo> exits;
  for (auto it = children_.rbegin(); it != children_.rend(); ++it)
    if (!it->exited) kill(it->pid, SIGTERM);
  const int64_t deadline = mono_ns() + static_cast<int64_t>(grace.count()) * 1'000'000;
  while (running() > 0 && mono_ns() < deadline) {
    auto e = poll(20);
    exits.insert(exits.end(), e.begin(), e.end());
  }
  for (auto& c : children_)
    if (!c.exited) kill(c.pid, SIGKILL);
  while (running() > 0) {
    auto e = poll(20);
    exits.insert(exits.end(), e.begin(), e.end());
  }
  for (auto& c : children_) drain(c, true);
  return exits;
}

size_t ProcessGroup::running() const {
  size_t n = 0;
  for (const auto& c : children_)
    if (!c.exited) ++n;
  return n;
}

}  // namespace ephor::launcher
