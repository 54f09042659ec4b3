#include "common/lcm/bus.h"

#include <cstdlib>
#include <stdexcept>

#include <spdlog/spdlog.h>

namespace ephor {
namespace {
// Log the first few occurrences of a recurring problem, then every 1000th.
bool should_log(uint64_t count) { return count <= 5 || count % 1000 == 0; }
}  // namespace

std::string resolve_lcm_url(const std::string& flag_url) {
  if (!flag_url.empty()) return flag_url;
  if (const char* env = std::getenv("LCM_DEFAULT_URL"); env != nullptr && *env != '\0') return env;
  return kDefaultLcmUrl;
}

Bus::Bus(const std::string& url, std::string sender)
    : url_(resolve_lcm_url(url)), sender_(std::move(sender)), lcm_(url_) {
  if (!lcm_.good()) {
    throw std::runtime_error("cannot open LCM at '" + url_ +
                             "' (is there a multicast route? try: tools/ephor setup)");
  }
}

Bus::~Bus() { stop(); }

bool Bus::publish_raw(const std::string& channel, const void* data, int size) {
  std::lock_guard<std::mutex> lock(publish_mutex_);
  if (lcm_.publish(channel, data, static_cast<unsigned int>(size)) != 0) {
    spdlog::warn("bus: publish on {} ({} bytes) failed", channel, size);
    return false;
  }
  return true;
}

bool Bus::encode_failed(const std::string& channel) {
  spdlog::error("bus: cannot encode message for {} (array length fields inconsistent?)", channel);
  return false;
}

void Bus::add_subscription(const std::string& channel, std::unique_ptr<Subscription> sub) {
  std::lock_guard<std::mutex> lock(subs_mutex_);
  lcm::Subscription* s = lcm_.subscribe(channel, &Subscription::on_message, sub.get());
  // LCM 1.3.1 queues 30 messages per subscription and drops the newest when
  // full; handlers here are quick (mailboxes), a larger queue rides out bursts.
  if (s != nullptr) s->setQueueCapacity(200);
  subs_.push_back(std::move(sub));
}

int64_t Bus::next_seq(const std::string& channel) {
  std::lock_guard<std::mutex> lock(counters_mutex_);
  return seq_[channel]++;
}

void Bus::note_received(const std::string& channel) {
  std::lock_guard<std::mutex> lock(counters_mutex_);
  ++counters_[channel].received;
}

void Bus::note_decode_error(const std::string& channel, const char* type, int size) {
  uint64_t n = 0;
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    n = ++counters_[channel].decode_errors;
  }
  if (should_log(n)) {
    spdlog::warn("bus: dropped a message on {} that does not decode as {} ({} bytes); {} so far",
                 channel, type, size, n);
  }
}

void Bus::note_handler_error(const std::string& channel, const char* what) {
  uint64_t n = 0;
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    n = ++counters_[channel].handler_errors;
  }
  if (should_log(n)) {
    spdlog::error("bus: handler for {} rejected a message: {} ({} so far)", channel, what, n);
  }
}

bool Bus::handle(int timeout_ms) { return lcm_.handleTimeout(timeout_ms) > 0; }

void Bus::start() {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this] {
    while (running_.load()) lcm_.handleTimeout(50);
  });
}

void Bus::stop() {
  if (!running_.exchange(false)) return;
  if (thread_.joinable()) thread_.join();
}

ChannelCounters Bus::counters(const std::string& channel) const {
  std::lock_guard<std::mutex> lock(counters_mutex_);
  auto it = counters_.find(channel);
  return it == counters_.end() ? ChannelCounters{} : it->second;
}

uint64_t Bus::total_decode_errors() const {
  std::lock_guard<std::mutex> lock(counters_mutex_);
  uint64_t total = 0;
  for (const auto& [_, c] : counters_) total += c.decode_errors;
  return total;
}

}  // namespace ephor
