#include "common/display/newest_messages.h"

namespace ephor::display {

nlohmann::json NewestMessages::to_json() const {
  std::map<std::string, std::function<nlohmann::json()>> copy;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    copy = newest_;
  }
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [key, fn] : copy) j[key] = fn();
  return j;
}

}  // namespace ephor::display
