#pragma once
// TestChildProcess: starts an ephor binary for an integration test with its
// output in a log file, and stops it with SIGTERM (SIGKILL after 5 s). For
// tests only.

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace ephor::vision {

class TestChildProcess {
 public:
  // Starts $EPHOR_BIN_DIR/<exe> (or bin/<exe>) with `args`; output to `log_path`.
  // Throws std::runtime_error when it cannot be started.
  TestChildProcess(const std::string& exe, std::vector<std::string> args, std::string log_path)
      : log_path_(std::move(log_path)) {
    const char* dir = std::getenv("EPHOR_BIN_DIR");
    const std::string path = std::string(dir != nullptr ? dir : "bin") + "/" + exe;
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(path.c_str()));
    for (std::string& s : args) argv.push_back(s.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, log_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    const int rc = posix_spawn(&pid_, path.c_str(), &fa, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) throw std::runtime_error("cannot start " + path + ": " + std::strerror(rc));
  }
  ~TestChildProcess() {
    stop();
    std::remove(log_path_.c_str());
  }
  TestChildProcess(const TestChildProcess&) = delete;
  TestChildProcess& operator=(const TestChildProcess&) = delete;

  // SIGTERM, then waits up to 5 s. Returns "" on a clean exit (status 0),
  // else what happened. Idempotent.
  std::string stop() {
    if (pid_ <= 0) return "";
    kill(pid_, SIGTERM);
    int status = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    pid_t r = 0;
    while ((r = waitpid(pid_, &status, WNOHANG)) == 0 &&
           std::chrono::steady_clock::now() < deadline) {
      // Reaping a child has no condition variable.
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    std::string outcome;
    if (r == 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, &status, 0);
      outcome = "did not exit within 5 s of SIGTERM";
    } else if (!(WIFEXITED(status) && WEXITSTATUS(status) == 0)) {
      outcome = "exit status " + std::to_string(status);
    }
    pid_ = 0;
    return outcome;
  }

  std::string log() const {
    std::ifstream in(log_path_);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }

  // Waits until the log contains `text`.
  bool wait_log(const std::string& text, std::chrono::milliseconds timeout) const {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (log().find(text) == std::string::npos) {
      if (std::chrono::steady_clock::now() >= deadline) return false;
      // A child's log file has no condition variable.
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return true;
  }

 private:
  std::string log_path_;
  pid_t pid_ = 0;
};

}  // namespace ephor::vision
