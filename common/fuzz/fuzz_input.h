#pragma once
// Helpers shared by the fuzz targets (issue 18; see cmake/EphorFuzz.cmake).
//
// FuzzInputFile: the fuzzer's bytes as a file, for loaders that take only a
// path (they are fuzzed as the processes call them, file reading included).
// One in-memory file (memfd) per process, rewritten for each input and named
// /proc/self/fd/N, so a run does not touch the disk.
//
// FuzzNamedFile: the same as a file of a given name (for readers that pick
// their decoder by the name's extension, as OpenCV's video readers do), in a
// temporary folder of its own on disk, removed with the object.
//
// FuzzBytes: reads typed values off the fuzzer's bytes (as libFuzzer's
// FuzzedDataProvider, which the gcc build does not have), for targets that
// drive a state machine with a sequence of events. Past the end every value
// is 0 / false / empty. Floating-point values are raw bit patterns, so NaN,
// infinities, denormals and huge values all come up.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace ephor::fuzz {

class FuzzInputFile {
 public:
  FuzzInputFile();
  ~FuzzInputFile();
  FuzzInputFile(const FuzzInputFile&) = delete;
  FuzzInputFile& operator=(const FuzzInputFile&) = delete;

  // Replaces the file's contents with `size` bytes at `data`; returns path().
  const std::string& write(const uint8_t* data, size_t size);
  const std::string& path() const { return path_; }

 private:
  int fd_ = -1;
  std::string path_;
};

class FuzzNamedFile {
 public:
  explicit FuzzNamedFile(const std::string& name);
  ~FuzzNamedFile();
  FuzzNamedFile(const FuzzNamedFile&) = delete;
  FuzzNamedFile& operator=(const FuzzNamedFile&) = delete;

  // Replaces the file's contents with `size` bytes at `data`; returns path().
  const std::string& write(const uint8_t* data, size_t size);
  const std::string& path() const { return path_; }

 private:
  std::string dir_, path_;
};

class FuzzBytes {
 public:
  FuzzBytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}

  bool empty() const { return pos_ >= size_; }
  size_t remaining() const { return size_ - pos_; }

  template <typename T>
  T take() {
    T value{};
    unsigned char* out = reinterpret_cast<unsigned char*>(&value);
    for (size_t i = 0; i < sizeof(T) && pos_ < size_; ++i) out[i] = data_[pos_++];
    return value;
  }
  bool take_bool() { return (take<uint8_t>() & 1) != 0; }
  // A value in [lo, hi] (inclusive), from one or more bytes.
  int64_t take_in(int64_t lo, int64_t hi) {
    const uint64_t span = static_cast<uint64_t>(hi - lo) + 1;
    const uint64_t raw = span <= 256     ? take<uint8_t>()
                         : span <= 65536 ? take<uint16_t>()
                                         : take<uint64_t>();
    return lo + static_cast<int64_t>(span == 0 ? raw : raw % span);
  }
  // Up to `max_len` bytes as a string (length from one byte).
  std::string take_string(size_t max_len) {
    const size_t n = std::min<size_t>(take<uint8_t>(), max_len);
    std::string s;
    for (size_t i = 0; i < n && pos_ < size_; ++i) s.push_back(static_cast<char>(data_[pos_++]));
    return s;
  }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
};

// A stream of bus messages, for the targets that run a process's LCM
// handlers. Each record: a byte naming the channel (taken mod `channels`),
// two bytes of clock step (us / 4, little-endian: 0-262 ms), two bytes of
// length (little-endian), then that many bytes of the message as LCM encodes
// it. The stream ends at the first record that does not fit, one longer than
// `max_len`, or after `max_messages`.
struct FuzzMessage {
  int channel = 0;
  int64_t step_us = 0;
  const uint8_t* bytes = nullptr;
  int size = 0;

  // Decodes as the bus does: a message that does not decode to its full size
  // is dropped (false).
  template <typename T>
  bool decode(T& out) const {
    return out.decode(bytes, 0, size) == size;
  }
};

class FuzzMessageStream {
 public:
  FuzzMessageStream(const uint8_t* data, size_t size, int channels, size_t max_len = 4096,
                    int max_messages = 256)
      : data_(data), size_(size), channels_(channels), max_len_(max_len), left_(max_messages) {}

  bool next(FuzzMessage& m) {
    if (left_ <= 0 || pos_ + 5 > size_) return false;
    const uint8_t* r = data_ + pos_;
    const size_t len = static_cast<size_t>(r[3] | (r[4] << 8));
    if (len > max_len_ || len > size_ - pos_ - 5) return false;
    m.channel = r[0] % channels_;
    m.step_us = 4 * static_cast<int64_t>(r[1] | (r[2] << 8));
    m.bytes = r + 5;
    m.size = static_cast<int>(len);
    pos_ += 5 + len;
    --left_;
    return true;
  }

 private:
  const uint8_t* data_;
  size_t size_;
  int channels_;
  size_t max_len_;
  int left_;
  size_t pos_ = 0;
};

// Appends one record of a FuzzMessageStream: for seed corpora and unit tests.
template <typename T>
void append_message(std::vector<uint8_t>& out, int channel, int64_t step_us, const T& message) {
  const int n = message.getEncodedSize();
  std::vector<uint8_t> bytes(static_cast<size_t>(n));
  message.encode(bytes.data(), 0, n);
  const auto step = static_cast<uint16_t>(std::clamp<int64_t>(step_us / 4, 0, 65535));
  out.push_back(static_cast<uint8_t>(channel));
  out.push_back(static_cast<uint8_t>(step & 0xff));
  out.push_back(static_cast<uint8_t>(step >> 8));
  out.push_back(static_cast<uint8_t>(n & 0xff));
  out.push_back(static_cast<uint8_t>((n >> 8) & 0xff));
  out.insert(out.end(), bytes.begin(), bytes.end());
}

// A broken invariant: prints `what` and aborts, so libFuzzer (and the corpus
// runner) report the input as a crash.
[[noreturn]] void fail(const std::string& what);

// Fails unless the message encodes to its getEncodedSize() (LCM's encoder
// writes a string only up to a NUL byte, so a receiver would drop it).
template <typename T>
void check_encodes(const T& message, const std::string& what) {
  const int n = message.getEncodedSize();
  std::vector<uint8_t> bytes(static_cast<size_t>(n));
  if (message.encode(bytes.data(), 0, n) != n) fail(what + " does not encode");
}

// Every one of the n values finite.
inline bool all_finite(const double* v, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

}  // namespace ephor::fuzz
