#include "procs/shepherd/track/offline_tracker.h"

#include <cmath>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace ephor::track {
namespace {

// Image px -> "F" mm of a field the size of the image: x = u + 0.5,
// y = height - (v + 0.5), so the image's pixel area is exactly the field.
calibration::FieldCalibration image_field(int width, int height) {
  calibration::AffineMap m;
  m << 1.0, 0.0, 0.5, 0.0, -1.0, static_cast<double>(height) - 0.5;
  (void)width;
  return calibration::FieldCalibration(m, m, calibration::PlaneSetup{}, {}, {},
                                       "image-sized field, 1 mm per px (procs/shepherd/track)");
}

}  // namespace

const char* state_name(worldmodel::ObjectState state) {
  switch (state) {
    case worldmodel::ObjectState::kVisible:
      return "visible";
    case worldmodel::ObjectState::kObscured:
      return "obscured";
    case worldmodel::ObjectState::kDead:
      return "dead";
  }
  return "dead";
}

std::string to_json_line(const FrameTracks& frame) {
  nlohmann::json j;
  j["frame"] = frame.frame;
  j["t"] = frame.t_s;
  j["tracks"] = nlohmann::json::array();
  for (const auto& t : frame.tracks) {
    j["tracks"].push_back({{"id", t.id},
                           {"x", t.x},
                           {"y", t.y},
                           {"vx", t.vx},
                           {"vy", t.vy},
                           {"state", state_name(t.state)}});
  }
  return j.dump();
}

OfflineTracker::OfflineTracker(OfflineTrackerConfig config)
    : config_(std::move(config)), pipeline_(config_.vision, config_.settings) {}

OfflineTracker::~OfflineTracker() = default;

const worldmodel::WorldModelCounters* OfflineTracker::counters() const {
  return world_ ? &world_->counters() : nullptr;
}

FrameTracks OfflineTracker::process(const vision::ImageView& image, int64_t frame_index,
                                    double t_s) {
  if (!std::isfinite(t_s)) throw std::invalid_argument("frame time is not finite");
  if (const std::string bad = vision::check_image(image); !bad.empty()) {
    throw std::invalid_argument("frame " + std::to_string(frame_index) + ": " + bad);
  }
  if (!world_) {
    width_ = image.width;
    height_ = image.height;
    worldmodel::WorldModelConfig wc = config_.world;
    wc.workcell.field_length_mm = width_;
    wc.workcell.field_width_mm = height_;
    world_ = std::make_unique<worldmodel::WorldModel>(image_field(width_, height_), wc);
  } else if (image.width != width_ || image.height != height_) {
    throw std::invalid_argument("frame " + std::to_string(frame_index) + " is " +
                                std::to_string(image.width) + " x " + std::to_string(image.height) +
                                " px; the video started at " + std::to_string(width_) + " x " +
                                std::to_string(height_));
  }
  const vision::FrameResult r = pipeline_.process(image);
  if (r.status == vision::FrameStatus::kBadFrame) {
    throw std::invalid_argument("frame " + std::to_string(frame_index) + ": " + r.error);
  }
  FrameTracks out;
  out.frame = frame_index;
  out.t_s = t_s;
  out.threshold = r.threshold;
  worldmodel::BlobFrame blobs;
  blobs.utime_us = static_cast<int64_t>(std::llround(t_s * 1e6));
  blobs.frame_index = frame_index;
  for (const auto& b : *r.blobs)
    blobs.blobs.push_back({{static_cast<double>(b.u), static_cast<double>(b.v)}, b.area});
  out.blobs = static_cast<int>(blobs.blobs.size());
  if (world_->process(blobs) != worldmodel::WorldModel::FrameResult::kProcessed) {
    throw std::invalid_argument("frame " + std::to_string(frame_index) + " at " +
                                std::to_string(t_s) + " s is not after the previous frame");
  }
  for (const auto& o : world_->objects()) {
    out.tracks.push_back({o.id, o.position_px.x(), o.position_px.y(), o.velocity_px_s.x(),
                          o.velocity_px_s.y(), o.state});
  }
  return out;
}

}  // namespace ephor::track
