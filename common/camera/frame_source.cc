#include "common/camera/frame_source.h"

#include <sys/stat.h>

#include <cctype>
#include <cstdio>
#include <stdexcept>
#include <vector>

namespace ephor::camera {
namespace {

bool file_exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

bool all_digits(const std::string& s) {
  if (s.empty()) return false;
  for (const char c : s)
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  return true;
}

std::string format_index(const std::string& pattern, int index) {
  std::vector<char> buf(pattern.size() + 32);
  // The pattern was checked to hold exactly one integer conversion.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
  std::snprintf(buf.data(), buf.size(), pattern.c_str(), index);
#pragma GCC diagnostic pop
  return buf.data();
}

}  // namespace

const char* source_kind_name(SourceKind kind) {
  switch (kind) {
    case SourceKind::kVideoFile:
      return "video file";
    case SourceKind::kImageSequence:
      return "image sequence";
    case SourceKind::kDevice:
      return "V4L2 device";
  }
  return "?";
}

SourceKind classify_source(const std::string& spec) {
  if (spec.rfind("/dev/video", 0) == 0 || all_digits(spec)) return SourceKind::kDevice;
  if (spec.find('%') != std::string::npos) return SourceKind::kImageSequence;
  return SourceKind::kVideoFile;
}

std::string check_sequence_pattern(const std::string& pattern) {
  int conversions = 0;
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') continue;
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      ++i;
      continue;
    }
    size_t j = i + 1;
    while (j < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[j]))) ++j;
    if (j >= pattern.size() || (pattern[j] != 'd' && pattern[j] != 'u')) {
      return "'" + pattern.substr(i, j - i + 1) +
             "' is not an integer conversion (want e.g. %04d for frame numbers)";
    }
    ++conversions;
    i = j;
  }
  if (conversions != 1) {
    return "has " + std::to_string(conversions) +
           " frame-number conversions; want exactly one (e.g. frames/%04d.png)";
  }
  return "";
}

FrameSource::FrameSource(const std::string& spec) : spec_(spec), kind_(classify_source(spec)) {
  const std::string what = std::string(source_kind_name(kind_)) + " '" + spec + "'";
  if (spec.empty()) throw std::runtime_error("no camera source given");
  switch (kind_) {
    case SourceKind::kVideoFile:
      if (!file_exists(spec)) throw std::runtime_error(what + ": no such file");
      break;
    case SourceKind::kImageSequence: {
      if (const std::string bad = check_sequence_pattern(spec); !bad.empty()) {
        throw std::runtime_error(what + ": bad pattern: " + bad);
      }
      // OpenCV starts a sequence at the first existing index of 0..4.
      bool found = false;
      for (int i = 0; i < 5 && !found; ++i) found = file_exists(format_index(spec, i));
      if (!found) {
        throw std::runtime_error(what + ": no file for frame 0..4 (e.g. '" + format_index(spec, 0) +
                                 "' does not exist)");
      }
      break;
    }
    case SourceKind::kDevice: {
      const std::string path = all_digits(spec) ? "/dev/video" + spec : spec;
      struct stat st {};
      if (::stat(path.c_str(), &st) != 0) throw std::runtime_error(what + ": no such device");
      break;
    }
  }
  open_capture();
  fps_ = capture_.get(cv::CAP_PROP_FPS);
  if (!(fps_ > 0.0 && fps_ <= 1000.0)) fps_ = 0.0;
}

void FrameSource::open_capture() {
  const std::string what = std::string(source_kind_name(kind_)) + " '" + spec_ + "'";
  bool opened = false;
  try {
    if (kind_ == SourceKind::kDevice) {
      const std::string digits =
          all_digits(spec_) ? spec_ : spec_.substr(std::string("/dev/video").size());
      opened = all_digits(digits) ? capture_.open(std::stoi(digits), cv::CAP_V4L2)
                                  : capture_.open(spec_, cv::CAP_V4L2);
    } else if (kind_ == SourceKind::kImageSequence) {
      opened = capture_.open(spec_, cv::CAP_IMAGES);
    } else {
      opened = capture_.open(spec_, cv::CAP_ANY);
    }
  } catch (const cv::Exception& e) {
    throw std::runtime_error(what + ": OpenCV cannot open it: " + e.what());
  }
  if (!opened || !capture_.isOpened()) {
    throw std::runtime_error(what + (kind_ == SourceKind::kDevice
                                         ? ": cannot open the device (busy, no permission, or "
                                           "not a capture device?)"
                                         : ": OpenCV cannot decode it"));
  }
  // OpenCV's own AVI reader asserts (cv::Exception) on a corrupt chunk.
  bool read = false;
  try {
    read = capture_.read(first_);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(what + ": cannot decode its first frame: " + e.what());
  }
  if (!read || first_.empty()) {
    throw std::runtime_error(what + ": no frame could be read (empty or undecodable)");
  }
  first_pending_ = true;
  width_ = first_.cols;
  height_ = first_.rows;
}

bool FrameSource::read(cv::Mat& frame) {
  if (first_pending_) {
    first_pending_ = false;
    frame = first_;
    return true;
  }
  cv::Mat next;
  bool read = false;
  try {
    read = capture_.read(next);
  } catch (const cv::Exception& e) {
    // OpenCV's own AVI reader asserts on a corrupt chunk (found by the fuzz
    // target video_file_camera).
    throw std::runtime_error(std::string(source_kind_name(kind_)) + " '" + spec_ +
                             "': cannot decode the next frame: " + e.what());
  }
  if (!read || next.empty()) return false;
  frame = next;
  return true;
}

void FrameSource::rewind() {
  if (kind_ == SourceKind::kDevice) return;
  capture_.release();
  open_capture();
}

}  // namespace ephor::camera
