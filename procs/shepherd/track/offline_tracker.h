#pragma once
// OfflineTracker: the vision library (procs/shepherd/vision: ForegroundImage,
// threshold, blobify) and the world model (procs/shepherd/worldmodel: association and
// the double alpha-beta filter) run frame by frame on recorded video, with no
// processes and no LCM: `tools/ephor track`.
//
// A real video has no field calibration, so the world model is given one
// that maps the image onto a "field" of the image's own size (1 mm per px, y
// flipped so that F's y points up as in the system): every blob in the image
// is inside the field, and positions and velocities are reported in image
// px and px/s.
//
// Not thread-safe; one owner.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/shepherd/vision/image_view.h"
#include "common/shepherd/vision/vision_pipeline.h"
#include "common/shepherd/worldmodel/world_model.h"

namespace ephor::track {

struct OfflineTrackerConfig {
  vision::PipelineConfig vision;
  vision::VisionSettings settings;  // threshold kThresholdAuto or a fixed grey level
  worldmodel::WorldModelConfig world;
};

// One track of one frame, image px (u right, v down) and px/s.
struct TrackState {
  int id = 0;
  double x = 0.0;   // u, px
  double y = 0.0;   // v, px
  double vx = 0.0;  // px/s
  double vy = 0.0;  // px/s
  worldmodel::ObjectState state = worldmodel::ObjectState::kVisible;
};

struct FrameTracks {
  int64_t frame = 0;
  double t_s = 0.0;  // frame time from the first frame, s
  int blobs = 0;     // blobs vision found in this frame
  int threshold = -1;
  std::vector<TrackState> tracks;
};

const char* state_name(worldmodel::ObjectState state);  // visible / obscured / dead

// {"frame": i, "t": s, "tracks": [{"id","x","y","vx","vy","state"}]} on one line.
std::string to_json_line(const FrameTracks& frame);

class OfflineTracker {
 public:
  // Throws std::invalid_argument naming the field when the configuration is bad.
  explicit OfflineTracker(OfflineTrackerConfig config);
  ~OfflineTracker();

  // Tracks one frame taken at t_s (s, increasing). The first frame fixes the
  // image size; a frame of another size is an error. Throws
  // std::invalid_argument naming the problem for a bad image or time.
  FrameTracks process(const vision::ImageView& image, int64_t frame_index, double t_s);

  const worldmodel::WorldModelCounters* counters() const;

 private:
  OfflineTrackerConfig config_;
  vision::VisionPipeline pipeline_;
  std::unique_ptr<worldmodel::WorldModel> world_;  // made at the first frame (its size)
  int width_ = 0;
  int height_ = 0;
};

}  // namespace ephor::track
