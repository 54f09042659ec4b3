#include "common/runtime/cpu_latency_request.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>

namespace ephor {

CpuLatencyRequest::CpuLatencyRequest(int max_latency_us, const std::string& path) {
  if (max_latency_us < 0) {
    error_ = "a latency request must be >= 0 us (got " + std::to_string(max_latency_us) + ")";
    return;
  }
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) {
    error_ = "cannot open " + path + ": " + std::strerror(errno);
    return;
  }
  // The PM QoS interface takes the value as a binary 32-bit integer.
  const int32_t value = max_latency_us;
  if (::write(fd, &value, sizeof value) != static_cast<ssize_t>(sizeof value)) {
    error_ = "cannot write " + path + ": " + std::strerror(errno);
    ::close(fd);
    return;
  }
  fd_ = fd;
}

CpuLatencyRequest::~CpuLatencyRequest() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace ephor
