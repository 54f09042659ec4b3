#include "common/shepherd/vision/vision_pipeline.h"

#include <stdexcept>

namespace ephor::vision {

std::string check_settings(const VisionSettings& s) {
  if (s.mode != SearchMode::kBlobify && s.mode != SearchMode::kTrackify) {
    return "mode " + std::to_string(static_cast<int>(s.mode)) +
           " is neither BLOBIFY (0) nor TRACKIFY (1)";
  }
  if (s.scan != ScanMode::kFull && s.scan != ScanMode::kAxis) {
    return "scan " + std::to_string(static_cast<int>(s.scan)) + " is neither FULL (0) nor AXIS (1)";
  }
  if (s.threshold != kThresholdAuto && (s.threshold < 1 || s.threshold > 254)) {
    return "threshold " + std::to_string(s.threshold) + " is neither 1..254 nor AUTO (-1)";
  }
  return "";
}

VisionPipeline::VisionPipeline(PipelineConfig config, VisionSettings settings)
    : foreground_(config.foreground),
      selector_(config.threshold),
      blobifier_(config.blobifier),
      trackifier_(config.trackifier) {
  const std::string problem = apply(settings);
  if (!problem.empty()) throw std::invalid_argument("vision settings: " + problem);
  pick_pending_ = settings.threshold == kThresholdAuto;
}

std::string VisionPipeline::apply(const VisionSettings& settings) {
  std::string problem = check_settings(settings);
  if (!problem.empty()) return problem;
  if (settings.threshold == kThresholdAuto) {
    if (settings_.threshold != kThresholdAuto) pick_pending_ = true;
  } else {
    threshold_ = settings.threshold;
    pick_pending_ = false;
  }
  // Entering trackify, or changing how blobs are measured, starts from a full
  // search so no blob carried over was measured differently.
  if (settings.mode != settings_.mode || settings.scan != settings_.scan ||
      settings.threshold != settings_.threshold) {
    trackifier_.reset();
  }
  settings_ = settings;
  return "";
}

FrameResult VisionPipeline::process(const ImageView& image) {
  FrameResult out;
  out.blobs = &empty_;
  out.mode = settings_.mode;
  out.scan = settings_.scan;
  out.threshold = threshold_;
  if (settings_.paused) {
    out.status = FrameStatus::kPaused;
    return out;
  }
  const std::string problem = check_image(image);
  if (!problem.empty()) {
    out.status = FrameStatus::kBadFrame;
    out.error = problem;
    return out;
  }
  return search(foreground_.apply(image), out);
}

FrameResult VisionPipeline::search(const ImageView& image, FrameResult& out) {
  if (pick_pending_) {
    last_choice_ = selector_.select(image);
    threshold_ = last_choice_.threshold;
    out.threshold_picked = true;
    // An empty field has no object peak yet: keep trying on later frames.
    pick_pending_ = last_choice_.status != ThresholdStatus::kOk;
    trackifier_.reset();
  }
  out.threshold = threshold_;
  out.threshold_provisional = settings_.threshold == kThresholdAuto && pick_pending_;
  const auto thr = static_cast<uint8_t>(threshold_);
  if (settings_.mode == SearchMode::kTrackify) {
    out.blobs = &trackifier_.track(blobifier_, image, thr, settings_.scan);
    out.full_search = trackifier_.last_was_full();
  } else {
    out.blobs = &blobifier_.blobify(image, thr, settings_.scan);
    out.full_search = true;
  }
  out.status = FrameStatus::kOk;
  return out;
}

}  // namespace ephor::vision
