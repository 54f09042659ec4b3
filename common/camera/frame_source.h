#pragma once
// FrameSource: frames from a video file, an image-sequence pattern
// (frames/%04d.png, printf-style, as OpenCV's VideoCapture reads them) or a
// V4L2 device (/dev/videoN, or just N) through OpenCV's VideoCapture.
//
// open() checks what it can before any frame is read, so a bad argument is
// named at start-up: a file that does not exist, a pattern without exactly
// one integer conversion or with no file for its first indices, a device
// that does not exist or cannot be opened, a file OpenCV cannot decode (its
// first frame is read at open). Errors are std::runtime_error messages that
// name the source.
//
// Not thread-safe: one owner (the camera task).

#include <memory>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

namespace ephor::camera {

enum class SourceKind { kVideoFile, kImageSequence, kDevice };

const char* source_kind_name(SourceKind kind);

// What `spec` names, by its form: "/dev/video*" or all digits -> device; a
// '%' -> image sequence; anything else -> video file.
SourceKind classify_source(const std::string& spec);

// "" when `pattern` has exactly one printf integer conversion (%d, %04d, ...)
// and no other '%' (except "%%"), else the problem.
std::string check_sequence_pattern(const std::string& pattern);

class FrameSource {
 public:
  // Opens `spec` and reads its first frame. Throws std::runtime_error naming
  // the source and the problem (see above).
  explicit FrameSource(const std::string& spec);

  // The next frame (BGR, grey, ... as decoded); false at the end of a file or
  // sequence, or when a device stops delivering. `frame` is then unchanged.
  // Throws std::runtime_error naming the source when OpenCV fails on the
  // frame (a corrupt file).
  bool read(cv::Mat& frame);
  // Starts a file or sequence again from its first frame (for --loop).
  // Throws std::runtime_error if it cannot be reopened. No-op for a device.
  void rewind();

  // Frames per second the source states (CAP_PROP_FPS); 0 when it states
  // none or an implausible value (image sequences, some devices).
  double stated_fps() const { return fps_; }
  SourceKind kind() const { return kind_; }
  const std::string& spec() const { return spec_; }
  int width() const { return width_; }    // px, of the first frame
  int height() const { return height_; }  // px

 private:
  void open_capture();

  std::string spec_;
  SourceKind kind_;
  cv::VideoCapture capture_;
  cv::Mat first_;  // read at open, returned by the first read()
  bool first_pending_ = false;
  double fps_ = 0.0;
  int width_ = 0;
  int height_ = 0;
};

}  // namespace ephor::camera
