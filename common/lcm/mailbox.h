#pragma once
// Mailbox<T>: keeps only the newest message of one channel (NASREM's rule: a
// cyclic process always works on the most recent data and never waits for a
// particular message). Written by the LCM thread, read by task threads.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <utility>

namespace ephor {

template <class T>
class Mailbox {
 public:
  // Stores `msg`, replacing any message not yet taken (counted as overwritten).
  void put(T msg) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (fresh_) ++overwritten_;
      value_ = std::move(msg);
      fresh_ = true;
      ++received_;
    }
    cv_.notify_all();
  }

  // The newest message if one arrived since the last take(); marks it taken.
  std::optional<T> take() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!fresh_) return std::nullopt;
    fresh_ = false;
    return value_;
  }

  // The newest message ever received (taken or not), without marking it.
  std::optional<T> latest() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return value_;
  }

  // Waits up to `timeout` for a message not yet taken, then takes it.
  template <class Rep, class Period>
  std::optional<T> wait_take(std::chrono::duration<Rep, Period> timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!cv_.wait_for(lock, timeout, [this] { return fresh_; })) return std::nullopt;
    fresh_ = false;
    return value_;
  }

  // Total messages put since construction.
  uint64_t received() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return received_;
  }
  // Messages replaced before anyone took them.
  uint64_t overwritten() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return overwritten_;
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::optional<T> value_;
  bool fresh_ = false;
  uint64_t received_ = 0;
  uint64_t overwritten_ = 0;
};

}  // namespace ephor
