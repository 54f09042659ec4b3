#pragma once
// Bus: ephor's small wrapper around lcm::LCM.
//
// - The URL comes from a flag, else LCM_DEFAULT_URL, else kDefaultLcmUrl
//   (TTL 0: nothing leaves this host; a 16 MB receive buffer so camera
//   frames are not dropped).
// - publish() fills in a message's `header` (sender, sequence number, time)
//   when the type has one.
// - subscribe<T>() decodes on the LCM thread and calls back there; a message
//   that does not decode, or a callback that throws, is counted and logged and
//   never leaves the LCM thread.
// - mailbox<T>() keeps the newest message of a channel for task threads.
//
// Threading: publish() may be called from any thread. Callbacks run on the
// thread that calls handle() / the thread started by start().

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "common/lcm/mailbox.h"
#include "common/time/clock.h"

namespace ephor {

inline constexpr const char* kDefaultLcmUrl =
    "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=16777216";

// flag_url if not empty, else $LCM_DEFAULT_URL if set, else kDefaultLcmUrl.
std::string resolve_lcm_url(const std::string& flag_url);

struct ChannelCounters {
  uint64_t received = 0;        // messages that decoded
  uint64_t decode_errors = 0;   // messages that did not decode as the subscribed type
  uint64_t handler_errors = 0;  // callbacks that threw
};

class Bus {
 public:
  // Throws std::runtime_error naming the URL when LCM cannot be initialised.
  Bus(const std::string& url, std::string sender);
  ~Bus();
  Bus(const Bus&) = delete;
  Bus& operator=(const Bus&) = delete;

  const std::string& url() const { return url_; }
  const std::string& sender() const { return sender_; }

  // Encodes and sends `msg`. Fills msg.header (utime, sender, seq) when T has
  // a header_t member named `header`. Returns false (and logs) on failure.
  template <class T>
  bool publish(const std::string& channel, T& msg) {
    if constexpr (requires { msg.header.sender; }) {
      msg.header.utime = wall_us();
      msg.header.sender = sender_;
      msg.header.seq = next_seq(channel);
    }
    const int size = msg.getEncodedSize();
    std::vector<uint8_t> buf(static_cast<size_t>(size));
    if (msg.encode(buf.data(), 0, size) != size) return encode_failed(channel);
    return publish_raw(channel, buf.data(), size);
  }

  bool publish_raw(const std::string& channel, const void* data, int size);

  // Calls `fn` with every message on `channel` that decodes as T.
  template <class T>
  void subscribe(const std::string& channel, std::function<void(const T&)> fn) {
    add_subscription(channel, std::make_unique<Typed<T>>(this, T::getTypeName(), std::move(fn)));
  }

  // Keeps the newest message of `channel` (see Mailbox).
  template <class T>
  std::shared_ptr<Mailbox<T>> mailbox(const std::string& channel) {
    auto box = std::make_shared<Mailbox<T>>();
    subscribe<T>(channel, [box](const T& msg) { box->put(msg); });
    return box;
  }

  // Handles at most one message, waiting up to timeout_ms. Returns true when
  // one was handled. Call from one thread only; not while start() runs.
  bool handle(int timeout_ms);
  // Starts / stops a thread that handles messages until stop().
  void start();
  void stop();

  ChannelCounters counters(const std::string& channel) const;
  uint64_t total_decode_errors() const;

 private:
  struct Subscription {
    virtual ~Subscription() = default;
    virtual void on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel) = 0;
  };
  template <class T>
  struct Typed : Subscription {
    Typed(Bus* b, const char* type, std::function<void(const T&)> f)
        : bus(b), type_name(type), fn(std::move(f)) {}
    void on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel) override {
      T msg;
      const int size = static_cast<int>(rbuf->data_size);
      // lcm-gen's decoders can throw (std::bad_alloc, std::length_error) on
      // counts the bounds patch (cmake/lcm_bound_counts.sed) does not catch:
      // a message that does not decode must never end the process.
      bool decoded = false;
      try {
        decoded = msg.decode(rbuf->data, 0, size) == size;
      } catch (...) {
        decoded = false;
      }
      if (!decoded) {
        bus->note_decode_error(channel, type_name, size);
        return;
      }
      bus->note_received(channel);
      try {
        fn(msg);
      } catch (const std::exception& e) {
        bus->note_handler_error(channel, e.what());
      } catch (...) {
        bus->note_handler_error(channel, "unknown exception");
      }
    }
    Bus* bus;
    const char* type_name;
    std::function<void(const T&)> fn;
  };

  void add_subscription(const std::string& channel, std::unique_ptr<Subscription> sub);
  int64_t next_seq(const std::string& channel);
  bool encode_failed(const std::string& channel);
  void note_received(const std::string& channel);
  void note_decode_error(const std::string& channel, const char* type, int size);
  void note_handler_error(const std::string& channel, const char* what);

  std::string url_;
  std::string sender_;
  lcm::LCM lcm_;
  std::mutex publish_mutex_;
  std::mutex subs_mutex_;
  std::vector<std::unique_ptr<Subscription>> subs_;
  mutable std::mutex counters_mutex_;
  std::map<std::string, ChannelCounters> counters_;
  std::map<std::string, int64_t> seq_;
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace ephor
