// Integration test of ephor-comm as a real process: this test plays the
// planner and a fake arm over LCM. Registered with NETNS (a private network
// namespace, default LCM URL); run plainly it uses a private port instead so
// it cannot hear other LCM traffic on the host.

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/runtime/channels.h"
#include "common/time/clock.h"
#include "ephor/arm_ack_t.hpp"
#include "ephor/arm_cmd_t.hpp"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/motion_done_t.hpp"
#include "ephor/task_register_t.hpp"

extern char** environ;

namespace ephor::comm {
namespace {

using namespace std::chrono_literals;

// Copies of the message constants: gtest takes its arguments by reference, and
// the generated `static const` members have no out-of-line definition.
constexpr int8_t kStatusDone = motion_done_t::STATUS_DONE;
constexpr int8_t kStatusRejected = motion_done_t::STATUS_REJECTED;

// In the test's network namespace the default URL is private; outside it a
// port of our own keeps other processes' traffic out.
std::string test_lcm_url() {
  const char* in_netns = std::getenv("EPHOR_IN_NETNS");
  if (in_netns != nullptr && std::string(in_netns) == "1") return resolve_lcm_url("");
  const int port = 20000 + static_cast<int>(getpid() % 20000);
  return "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0";
}

std::string bin_dir() {
  const char* dir = std::getenv("EPHOR_BIN_DIR");
  return dir != nullptr ? dir : "bin";
}

// Everything the callbacks record, guarded by one mutex; waiters wake on any change.
class Recorder {
 public:
  template <class F>
  void update(F&& f) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      f();
    }
    cv_.notify_all();
  }
  // Waits until pred() (called under the lock) holds, up to `timeout`.
  bool wait(const std::function<bool()>& pred, std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, timeout, pred);
  }
  template <class F>
  auto read(F&& f) {
    std::lock_guard<std::mutex> lock(mutex_);
    return f();
  }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
};

// The arm's side of the contract, as procs/shared/arm implements it: a command is
// (seq, utime), executed at most once; a repeat is answered with the newest
// ack for it; a command not seen before that is older than 500 ms is refused
// as stale. Losses are simulated two ways: the first transmissions of every
// seq are not heard at all, or are executed but their acks are lost.
// Publishes arm state at 100 Hz.
class FakeArm {
 public:
  FakeArm(const std::string& url, Recorder& rec) : bus_(url, "arm"), rec_(rec) {
    bus_.subscribe<arm_cmd_t>(channels::kArmCmd, [this](const arm_cmd_t& m) { on_cmd(m); });
    bus_.start();
    state_thread_ = std::thread([this] { publish_state(); });
  }
  ~FakeArm() {
    rec_.update([this] { stop_ = true; });
    state_thread_.join();
    bus_.stop();
  }
  void ignore_first_transmissions(int n) {
    rec_.update([&] { ignore_first_ = n; });
  }
  void lose_first_acks(int n) {
    rec_.update([&] { lose_first_acks_ = n; });
  }
  // Caller holds the recorder's lock (use inside Recorder::wait/read).
  const std::vector<arm_cmd_t>& received() const { return received_; }
  const std::map<int64_t, int>& executions() const { return executions_; }
  const std::map<int64_t, int>& executions_of_goal() const { return executions_of_goal_; }
  // Planner publish -> arm receipt of the goal's first command, us (one host's clock).
  const std::map<int64_t, int64_t>& first_cmd_latency_us() const { return first_cmd_latency_us_; }

 private:
  void on_cmd(const arm_cmd_t& m) {
    std::optional<arm_ack_t> reply;
    std::optional<arm_ack_t> done;
    const int64_t arrival_us = wall_us();
    rec_.update([&] {
      // The test sets source_frame_utime to the goal's publish time.
      first_cmd_latency_us_.emplace(m.goal_id, arrival_us - m.source_frame_utime);
      received_.push_back(m);
      const int seen = ++transmissions_[m.seq];
      if (seen <= ignore_first_) return;  // the command was lost
      const bool acks_lost = seen - ignore_first_ <= lose_first_acks_;
      const std::pair<int64_t, int64_t> key{m.seq, m.utime};
      auto it = ledger_.find(key);
      if (it != ledger_.end()) {
        if (!acks_lost) reply = it->second;
        return;
      }
      arm_ack_t ack{};
      ack.seq = m.seq;
      ack.goal_id = m.goal_id;
      if (arrival_us - m.utime > 500'000) {
        ack.status = arm_ack_t::STATUS_REJECTED;
        ack.reason = "stale";
        ledger_[key] = ack;
        if (!acks_lost) reply = ack;
        return;
      }
      ++executions_[m.seq];
      ++executions_of_goal_[m.goal_id];
      ack.status = arm_ack_t::STATUS_ACCEPTED;
      ack.planned_duration_s = 0.05f;
      if (!acks_lost) reply = ack;
      // The motion is instantaneous here: DONE follows at once.
      ack.status = arm_ack_t::STATUS_DONE;
      ack.planned_duration_s = 0.0f;
      ledger_[key] = ack;
      if (!acks_lost) done = ack;
      last_done_seq_ = m.seq;
    });
    if (reply) publish_ack(*reply);
    if (done) publish_ack(*done);
  }
  void publish_ack(arm_ack_t ack) {
    ack.utime = wall_us();
    bus_.publish(channels::kArmAck, ack);
  }
  void publish_state() {
    while (true) {
      arm_state_t s{};
      bool stop = false;
      rec_.read([&] {
        stop = stop_;
        s.last_done_seq = last_done_seq_;
      });
      if (stop) return;
      s.utime = wall_us();
      s.plane = arm_goal_t::PLANE_ELEVATION;
      bus_.publish(channels::kArmState, s);
      // A 100 Hz publisher's period, not synchronisation.
      std::this_thread::sleep_for(10ms);
    }
  }

  Bus bus_;
  Recorder& rec_;
  std::thread state_thread_;
  bool stop_ = false;
  int ignore_first_ = 0;
  int lose_first_acks_ = 0;
  int64_t last_done_seq_ = 0;
  std::map<int64_t, int64_t> first_cmd_latency_us_;
  std::vector<arm_cmd_t> received_;
  std::map<int64_t, int> transmissions_;
  std::map<int64_t, int> executions_;
  std::map<int64_t, int> executions_of_goal_;
  std::map<std::pair<int64_t, int64_t>, arm_ack_t> ledger_;  // (seq, utime) -> newest ack
};

class CommProcessTest : public ::testing::Test {
 protected:
  void SetUp() override {
    url_ = test_lcm_url();
    planner_ = std::make_unique<Bus>(url_, "planner");
    planner_->subscribe<motion_done_t>(channels::kMotionDone, [this](const motion_done_t& m) {
      rec_.update([&] { done_.push_back(m); });
    });
    planner_->subscribe<task_register_t>(channels::kTaskRegister, [this](const task_register_t& m) {
      if (m.process == "comm" && m.task == "relay")
        rec_.update([&] { registered_pids_.insert(m.pid); });
    });
    planner_->start();
    arm_ = std::make_unique<FakeArm>(url_, rec_);
    log_path_ = ::testing::TempDir() + "comm_process_test_" + std::to_string(getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".log";
    start_comm();
  }

  // Starts ephor-comm (output appended to the log) and waits until its relay
  // task has registered, i.e. it is subscribed and running.
  void start_comm() {
    const std::string exe = bin_dir() + "/ephor-comm";
    std::vector<std::string> argv_s = {
        exe,  "--name",     "comm", "--host",         "test", "--no-mlock", "--lcm-url",
        url_, "--retry-ms", "100",  "--max-attempts", "10",   "--arm-name", "arm"};
    std::vector<char*> argv;
    for (std::string& s : argv_s) argv.push_back(s.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, log_path_.c_str(), O_WRONLY | O_CREAT | O_APPEND,
                                     0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, exe.c_str(), &fa, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    ASSERT_EQ(rc, 0) << "cannot start " << exe << ": " << std::strerror(rc);
    pid_ = pid;
    ASSERT_TRUE(rec_.wait([this, pid] { return registered_pids_.count(pid) > 0; }, 10s))
        << "ephor-comm did not register its relay task within 10 s; log:\n"
        << comm_log();
  }

  // kill -9, as a crash: no clean shutdown.
  void crash_comm() {
    ASSERT_GT(pid_, 0);
    kill(pid_, SIGKILL);
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = 0;
  }

  void TearDown() override {
    stop_comm();
    arm_.reset();
    if (planner_) planner_->stop();
    // EPHOR_TEST_KEEP_LOGS=1 keeps ephor-comm's output for a look by hand.
    const char* keep = std::getenv("EPHOR_TEST_KEEP_LOGS");
    if (keep != nullptr && std::string(keep) == "1") {
      std::printf("ephor-comm log kept: %s\n", log_path_.c_str());
    } else {
      std::remove(log_path_.c_str());
    }
  }

  // SIGTERM, then expects a clean exit within 5 s (the log is complete after).
  void stop_comm() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      int status = 0;
      const auto deadline = std::chrono::steady_clock::now() + 5s;
      pid_t r = 0;
      while ((r = waitpid(pid_, &status, WNOHANG)) == 0 &&
             std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(10ms);  // reaping a child has no condition variable
      if (r == 0) {
        kill(pid_, SIGKILL);
        waitpid(pid_, &status, 0);
        ADD_FAILURE() << "ephor-comm did not exit within 5 s of SIGTERM";
      } else {
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
            << "ephor-comm exit status " << status << "; log:\n"
            << comm_log();
      }
      pid_ = 0;
    }
  }

  std::string comm_log() const {
    std::ifstream in(log_path_);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }

  void send_goal(int64_t id, float u, float v = 240.0f) {
    arm_goal_t g{};
    g.utime = wall_us();
    g.goal_id = id;
    g.plane = arm_goal_t::PLANE_ELEVATION;
    g.u = u;
    g.v = v;
    g.theta_rad = 0.25f;
    g.source_frame_utime = g.utime;
    g.target_object = -1;
    planner_->publish(channels::kArmGoal, g);
  }

  // Waits for the motion_done of `goal_id`.
  std::optional<motion_done_t> wait_done(int64_t goal_id, std::chrono::milliseconds timeout = 5s) {
    std::optional<motion_done_t> out;
    rec_.wait(
        [&] {
          for (const motion_done_t& d : done_)
            if (d.goal_id == goal_id) out = d;
          return out.has_value();
        },
        timeout);
    return out;
  }

  std::string url_;
  Recorder rec_;
  std::unique_ptr<Bus> planner_;
  std::unique_ptr<FakeArm> arm_;
  std::vector<motion_done_t> done_;
  std::set<pid_t> registered_pids_;
  std::string log_path_;
  pid_t pid_ = 0;
};

TEST_F(CommProcessTest, GoalComesBackDone) {
  send_goal(1, 256.0f);
  const auto done = wait_done(1);
  ASSERT_TRUE(done) << "no MOTION_DONE for goal 1; comm log:\n" << comm_log();
  EXPECT_EQ(done->status, kStatusDone) << done->reason;
  EXPECT_GE(done->seq, 1);
  EXPECT_EQ(done->attempts, 1);
  // A second goal once the first is done: the steady state (the first one may
  // wait for comm to hear the arm's state).
  send_goal(2, 300.0f);
  const auto done2 = wait_done(2);
  ASSERT_TRUE(done2) << "no MOTION_DONE for goal 2; comm log:\n" << comm_log();
  EXPECT_EQ(done2->status, kStatusDone) << done2->reason;
  EXPECT_EQ(done2->seq, done->seq + 1);
  rec_.read([&] {
    EXPECT_EQ(arm_->executions().size(), 2u);
    ASSERT_FALSE(arm_->received().empty());
    EXPECT_EQ(arm_->received().front().goal_id, 1);
    EXPECT_EQ(arm_->received().front().header.sender, "comm");
    EXPECT_FLOAT_EQ(arm_->received().front().u, 256.0f);
    // A figure for the log, not a test of speed.
    std::printf("planner publish -> arm receives ARM_CMD: goal 1 %.3f ms, goal 2 %.3f ms\n",
                static_cast<double>(arm_->first_cmd_latency_us().at(1)) / 1000.0,
                static_cast<double>(arm_->first_cmd_latency_us().at(2)) / 1000.0);
  });
  stop_comm();  // the log is complete once the process has exited
  for (const auto& d : {*done, *done2}) {
    const std::string line = "goal " + std::to_string(d.goal_id) + " seq " + std::to_string(d.seq) +
                             ": DONE after 1 attempt(s)";
    EXPECT_NE(comm_log().find(line), std::string::npos) << line << " not in:\n" << comm_log();
  }
}

TEST_F(CommProcessTest, ArmIgnoringTheFirstTwoTransmissionsStillExecutesOnce) {
  arm_->ignore_first_transmissions(2);
  send_goal(1, 100.0f);
  const auto done = wait_done(1);
  ASSERT_TRUE(done) << "no MOTION_DONE for goal 1; comm log:\n" << comm_log();
  EXPECT_EQ(done->status, kStatusDone) << done->reason;
  EXPECT_EQ(done->attempts, 3);
  rec_.read([&] {
    const auto& cmds = arm_->received();
    ASSERT_GE(cmds.size(), 3u);
    for (const arm_cmd_t& c : cmds) EXPECT_EQ(c.seq, done->seq) << "one goal, one seq";
    for (const arm_cmd_t& c : cmds)
      EXPECT_EQ(c.utime, cmds.front().utime) << "every transmission carries the first send's time";
    EXPECT_EQ(arm_->executions().size(), 1u);
    EXPECT_EQ(arm_->executions().at(done->seq), 1) << "executed exactly once";
  });
}

TEST_F(CommProcessTest, LostAcksAreRecoveredWithoutExecutingTheGoalAgain) {
  // The arm executes the first transmission but its two answers are lost;
  // the retransmission must be recognised as the same command.
  arm_->lose_first_acks(2);
  send_goal(1, 180.0f);
  const auto done = wait_done(1);
  ASSERT_TRUE(done) << "no MOTION_DONE for goal 1; comm log:\n" << comm_log();
  EXPECT_EQ(done->status, kStatusDone) << done->reason;
  EXPECT_EQ(done->attempts, 3);
  rec_.read([&] {
    EXPECT_EQ(arm_->executions_of_goal().at(1), 1) << "a retransmission was executed again";
    EXPECT_EQ(arm_->executions().size(), 1u);
  });
}

TEST_F(CommProcessTest, NanGoalIsRefusedAndNeverReachesTheArm) {
  send_goal(1, std::numeric_limits<float>::quiet_NaN());
  const auto refused = wait_done(1);
  ASSERT_TRUE(refused) << "no MOTION_DONE for the NaN goal; comm log:\n" << comm_log();
  EXPECT_EQ(refused->status, kStatusRejected);
  EXPECT_NE(refused->reason.find("not finite"), std::string::npos) << refused->reason;
  EXPECT_EQ(refused->attempts, 0);

  // A valid goal after it goes through, so the NaN one would have reached the arm by now.
  send_goal(2, 300.0f);
  const auto done = wait_done(2);
  ASSERT_TRUE(done) << comm_log();
  EXPECT_EQ(done->status, kStatusDone) << done->reason;
  rec_.read([&] {
    for (const arm_cmd_t& c : arm_->received()) {
      EXPECT_NE(c.goal_id, 1) << "the NaN goal reached the arm";
      EXPECT_TRUE(std::isfinite(c.u) && std::isfinite(c.v));
    }
    EXPECT_EQ(arm_->executions().size(), 1u);
  });
}

TEST_F(CommProcessTest, CrashedAndRestartedCommContinuesAboveTheArmsLastSeq) {
  send_goal(1, 120.0f);
  const auto done1 = wait_done(1);
  ASSERT_TRUE(done1) << comm_log();
  ASSERT_EQ(done1->status, kStatusDone) << done1->reason;

  crash_comm();
  start_comm();  // a fresh comm: its own counter would start at seq 1 again

  send_goal(2, 140.0f);
  const auto done2 = wait_done(2);
  ASSERT_TRUE(done2) << comm_log();
  EXPECT_EQ(done2->status, kStatusDone) << done2->reason;
  EXPECT_GT(done2->seq, done1->seq) << "the restarted comm reused a seq the arm had executed";
  rec_.read([&] {
    EXPECT_EQ(arm_->executions().size(), 2u) << "each goal executed once under its own seq";
    for (const auto& [seq, n] : arm_->executions()) EXPECT_EQ(n, 1) << "seq " << seq;
  });
}

TEST_F(CommProcessTest, AcksFromAnotherSenderAreIgnored) {
  // An impostor answers every command at once with REJECTED; the real arm
  // ignores the first two transmissions. If comm listened to the impostor the
  // goal would end REJECTED after one attempt.
  Bus impostor(url_, "mallory");
  impostor.subscribe<arm_cmd_t>(channels::kArmCmd, [&impostor](const arm_cmd_t& m) {
    arm_ack_t ack{};
    ack.utime = wall_us();
    ack.seq = m.seq;
    ack.goal_id = m.goal_id;
    ack.status = arm_ack_t::STATUS_REJECTED;
    ack.reason = "impostor";
    impostor.publish(channels::kArmAck, ack);
  });
  impostor.start();
  arm_->ignore_first_transmissions(2);
  send_goal(1, 200.0f);
  const auto done = wait_done(1);
  impostor.stop();
  ASSERT_TRUE(done) << comm_log();
  EXPECT_EQ(done->status, kStatusDone) << done->reason;
  EXPECT_EQ(done->attempts, 3);
  stop_comm();
  EXPECT_NE(comm_log().find("ignored message from sender 'mallory'"), std::string::npos)
      << comm_log();
}

}  // namespace
}  // namespace ephor::comm
