#pragma once
// A CPU wake-up latency request (Linux PM QoS, /dev/cpu_dma_latency), held
// for the lifetime of the object: the standard real-time setting that
// cyclictest also makes. With a request of 0 us the idle CPUs poll instead of
// halting, so a task woken by a timer or a message starts at once.
//
// Why it matters here: on a virtual machine a halted vCPU is handed back to
// the host, and waking it again can take milliseconds when the host runs
// something else on that core; an idle machine then had a slower pipeline
// than a busy one (frame capture to arm command p99 9-11 ms idle against
// 4 ms under load, README "Frame capture to arm command"). On real hardware
// it keeps the CPUs out of deep C-states. The cost is idle CPUs spinning.
//
// The kernel drops the request when the file is closed, so nothing outlives
// the process that holds it (no machine setting is changed).

#include <string>

namespace ephor {

class CpuLatencyRequest {
 public:
  static constexpr const char* kDefaultPath = "/dev/cpu_dma_latency";

  // Requests `max_latency_us` (>= 0) through `path`. Never throws: when the
  // file cannot be opened or written (not root, no PM QoS in this kernel)
  // held() is false and error() says why.
  explicit CpuLatencyRequest(int max_latency_us, const std::string& path = kDefaultPath);
  ~CpuLatencyRequest();
  CpuLatencyRequest(const CpuLatencyRequest&) = delete;
  CpuLatencyRequest& operator=(const CpuLatencyRequest&) = delete;

  bool held() const { return fd_ >= 0; }
  const std::string& error() const { return error_; }

 private:
  int fd_ = -1;
  std::string error_;
};

}  // namespace ephor
