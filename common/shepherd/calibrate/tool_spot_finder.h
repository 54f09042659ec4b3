#pragma once
// ToolSpotFinder: finds the calibration light on the tool tip in the
// overhead camera's image, to sub-pixel accuracy.
//
// Method: two frames at the same arm pose, one with the light on and one with
// it off. Their difference is the light alone (plus noise, and whatever moved
// between the frames): the arm, the field's uneven lighting and the sheep's
// marks cancel, so the light is found even where it is no brighter than a
// mark. Pixels brighter by more than `min_contrast` form 4-connected
// components; exactly one of plausible size (within `gate_px` of the expected
// position, when one is given) must remain, or the frame pair is rejected
// with the reason. Its centre is the difference-weighted centroid over a disc
// a few pixels larger than the component (signed weights, so the noise
// averages out instead of biasing the centroid).
//
// Frames: image px (u right, v down, origin at the centre of the top-left
// pixel), as camera_frame_t.
//
// Stateless apart from its configuration; thread-safe.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace ephor::calibrate {

// An 8-bit monochrome frame, row-major, row 0 at the top.
struct GreyFrame {
  int width = 0;   // px
  int height = 0;  // px
  std::vector<uint8_t> data;
};

struct ToolSpotFinderConfig {
  double min_contrast = 60.0;     // grey levels: on - off above this is light
  double min_area_px = 50.0;      // smaller: noise, or the edge of a mark that moved between frames
  double max_area_px = 600.0;     // larger ones are not the light (something moved)
  double window_margin_px = 3.0;  // centroid disc: component radius + this
  double gate_px = 40.0;          // around the expected position, when given
};

struct ToolSpot {
  Eigen::Vector2d centre_px;  // sub-pixel centre, px
  double area_px = 0.0;       // pixels above min_contrast
  double contrast = 0.0;      // largest on - off difference, grey levels
};

// The spot, or why there is none.
struct SpotResult {
  std::optional<ToolSpot> spot;
  std::string reason;  // empty when found
};

class ToolSpotFinder {
 public:
  // Throws std::invalid_argument for a non-finite or inconsistent config.
  explicit ToolSpotFinder(ToolSpotFinderConfig config = {});

  // `lit` and `dark`: frames with the light on and off at the same arm pose
  // (same size). `expected_px`: where the light should be, if known.
  SpotResult find(const GreyFrame& lit, const GreyFrame& dark,
                  const std::optional<Eigen::Vector2d>& expected_px = std::nullopt) const;

  const ToolSpotFinderConfig& config() const { return config_; }

 private:
  ToolSpotFinderConfig config_;
};

}  // namespace ephor::calibrate
