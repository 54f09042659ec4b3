#pragma once
// VisionPipeline: one camera frame in, its blobs out. Owns the run-time mode
// the display's buttons set in the paper (section 3.3): paused (the "scan"
// button), blobify or trackify, full or axis scan, and the threshold (picked
// from the first frame's histogram, or fixed by command).
//
// Settings are full state (shepherd_vision_cmd_t): applying the same settings twice
// changes nothing. Threshold kThresholdAuto picks the threshold again from
// the histogram of the next frame when it is newly set (a change from a
// fixed threshold, or the first settings); while no object peak has been
// seen (an empty field) a provisional threshold is used and the pick is
// retried on every frame.
//
// Not thread-safe: call from the vision task only.

#include <cstdint>
#include <string>
#include <vector>

#include "common/shepherd/vision/blobifier.h"
#include "common/shepherd/vision/foreground_image.h"
#include "common/shepherd/vision/image_view.h"
#include "common/shepherd/vision/threshold_selector.h"
#include "common/shepherd/vision/trackifier.h"

namespace ephor::vision {

enum class SearchMode : int8_t {
  kBlobify = 0,   // search the whole image every frame
  kTrackify = 1,  // re-grow last frame's blobs, search the border band
};

inline constexpr int kThresholdAuto = -1;

struct VisionSettings {
  bool paused = false;
  SearchMode mode = SearchMode::kBlobify;
  ScanMode scan = ScanMode::kFull;
  int threshold = kThresholdAuto;  // 1..254, or kThresholdAuto
};

// "" when `s` is valid, else a message naming the bad field.
std::string check_settings(const VisionSettings& s);

struct PipelineConfig {
  // What "object" means before thresholding: bright marks (the paper's
  // field), dark objects, or motion (ForegroundImage). Fixed for the run.
  ForegroundConfig foreground;
  BlobifierConfig blobifier;
  TrackifierConfig trackifier;
  ThresholdSelectorConfig threshold;
};

enum class FrameStatus {
  kOk,        // searched; `blobs` holds the result (possibly empty)
  kPaused,    // not searched (paused)
  kBadFrame,  // not searched; `error` says why
};

struct FrameResult {
  FrameStatus status = FrameStatus::kOk;
  std::string error;                         // set when status == kBadFrame
  const std::vector<Blob>* blobs = nullptr;  // valid until the next process(); never null
  int threshold = -1;                        // grey level used; a pixel > threshold is object
  bool threshold_provisional = false;        // no object peak seen yet (see ThresholdChoice)
  bool threshold_picked = false;             // the threshold was (re)picked on this frame
  SearchMode mode = SearchMode::kBlobify;
  ScanMode scan = ScanMode::kFull;
  bool full_search = false;  // the whole image was searched (blobify, or trackify's fallback)
};

class VisionPipeline {
 public:
  // Throws std::invalid_argument naming the field when `config` is out of range.
  explicit VisionPipeline(PipelineConfig config = {}, VisionSettings settings = {});

  // Applies `settings` (full state). Returns "" when applied, else a message
  // naming the bad field; the previous settings then stay in force.
  std::string apply(const VisionSettings& settings);
  const VisionSettings& settings() const { return settings_; }

  // Searches one frame (its ForegroundImage). Never throws for a bad image:
  // returns kBadFrame.
  FrameResult process(const ImageView& image);

  // Current threshold, -1 before the first frame in auto mode.
  int threshold() const { return threshold_; }
  const ThresholdChoice& last_threshold_choice() const { return last_choice_; }
  const BlobifierStats& blobifier_stats() const { return blobifier_.stats(); }

 private:
  FrameResult search(const ImageView& image, FrameResult& out);

  ForegroundImage foreground_;
  ThresholdSelector selector_;
  Blobifier blobifier_;
  Trackifier trackifier_;
  VisionSettings settings_;
  bool pick_pending_ = true;  // auto threshold must be (re)picked
  int threshold_ = -1;
  ThresholdChoice last_choice_;
  std::vector<Blob> empty_;
};

}  // namespace ephor::vision
