#pragma once
// Inbox<T>: a bounded FIFO from the LCM thread to a task, for channels where
// every message matters (comm's goals and acks, a scan's stripe images and
// profiles), unlike Mailbox<T>'s newest-only rule. When full (the task has
// stalled for seconds) the oldest message is dropped and counted.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <iterator>
#include <mutex>
#include <utility>
#include <vector>

namespace ephor {

template <class T>
class Inbox {
 public:
  explicit Inbox(size_t capacity) : capacity_(capacity) {}

  // Appends `msg`; returns false when the oldest message had to be dropped
  // to make room.
  bool push(T msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    bool kept_all = true;
    if (queue_.size() >= capacity_) {
      queue_.pop_front();
      ++dropped_;
      kept_all = false;
    }
    queue_.push_back(std::move(msg));
    return kept_all;
  }

  // Every message waiting, oldest first; the inbox is empty afterwards.
  std::vector<T> drain() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<T> out(std::make_move_iterator(queue_.begin()),
                       std::make_move_iterator(queue_.end()));
    queue_.clear();
    return out;
  }

  // Messages dropped because the inbox was full.
  uint64_t dropped() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return dropped_;
  }

 private:
  const size_t capacity_;
  mutable std::mutex mutex_;
  std::deque<T> queue_;
  uint64_t dropped_ = 0;
};

}  // namespace ephor
