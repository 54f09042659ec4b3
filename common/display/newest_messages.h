#pragma once
// NewestMessages: the newest message of every channel a display heard, for
// the debug dump (GET /api/debug). A message is kept as a copy and turned
// into JSON only when the dump is asked for, through the to_json() that the
// page's LCM-to-JSON file declares for its type (lcm_json.h for the shared
// types). Thread-safe: the LCM thread puts, HTTP threads read.

#include <functional>
#include <map>
#include <mutex>
#include <string>

#include <nlohmann/json.hpp>

namespace ephor::display {

class NewestMessages {
 public:
  // Keeps a copy of `msg` as `key`'s newest (key: the channel, or channel/host).
  template <class T>
  void put(const std::string& key, const T& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    newest_[key] = [msg]() { return nlohmann::json(msg); };
  }
  // {key: message as JSON} for every key put so far.
  nlohmann::json to_json() const;

 private:
  mutable std::mutex mutex_;
  std::map<std::string, std::function<nlohmann::json()>> newest_;
};

}  // namespace ephor::display
