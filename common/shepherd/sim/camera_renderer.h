#pragma once
// CameraRenderer: the overhead camera of paper 003 (section 2.3) - 512 x 482
// 8-bit monochrome frames in which a threshold separates the sheep's bright
// "wool" marks from everything else.
//
// Grey levels (before lighting and noise; defaults in CameraConfig):
//   surroundings (off the table)  15   darker than the field
//   arm (links, wrist, tool)      28   dark grey, darker than the field
//   field (the table)             40   the histogram's dominant, background peak
//   sheep body                    52   "slightly brighter than the field"
//   wool mark                    240   the object peak
// Why these: the vision chooses its threshold from the histogram, between the
// background peak and the object peak, 80-90 % of the way toward the object
// (section 2.3): about 205 here. Everything but the marks sits in one
// contiguous dark lobe (the bodies overlap the field's lobe under noise and
// lighting, the arm lies between surroundings and field), so no body or arm
// lobe can pass for the object peak, even with one sheep and the arm covering
// ten times the marks' area. The arm is drawn last, over everything (it is
// always above the sheep), so it hides every mark it passes over but never
// looks like a sheep itself.
//
// Geometry: each point is projected with its true height in F, so the marks
// (z = mark_height) and the arm's parts (at their own heights) appear where a
// pinhole camera would put them. Marks, bodies and arm parts are antialiased
// by pixel coverage (a one-pixel ramp across each edge), which keeps the
// intensity-weighted centroid of a mark within a few hundredths of a pixel of
// the projected mark centre.
//
// Lighting and noise: pixel = gain(u, v) * grey + N(0, noise_sigma), rounded
// and clamped to [0, 255]. The gain is a smooth linear ramp across the image
// (+- gain_gradient at the image corners along gain_direction_rad) times a
// mild radial fall-off (vignette). Noise comes from a fixed table of Gaussian
// samples read from a random offset each frame: cheap, and reproducible from
// the seed.
//
// Threading: not thread-safe; one owner renders.

#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "common/geometry/overhead_camera.h"
#include "common/shepherd/sim/cloud_field.h"
#include "common/shepherd/sim/world.h"

namespace ephor::sim {

struct CameraConfig {
  geometry::OverheadCamera camera;
  double surround_level = 15.0;  // grey levels, 0..255
  double field_level = 40.0;
  double body_level = 52.0;
  double arm_level = 28.0;
  double mark_level = 240.0;
  double noise_sigma = 2.5;         // grey levels, >= 0
  double gain_gradient = 0.06;      // gain 1 +- this at the image corners along the ramp
  double gain_direction_rad = 0.6;  // direction of increasing gain in the image (u right, v down)
  double vignette = 0.04;           // relative gain loss at the image corners
  // A mark counts as visible while less than this fraction of its area is hidden.
  double max_hidden_fraction = 0.5;
  uint64_t seed = 1;
};

// Throws std::invalid_argument naming the first bad field.
void validate(const CameraConfig& config);

// A part of the arm as the camera sees it: a capsule (a segment with a radius)
// in F, mm. Links, wrist, tool and the pedestal are all capsules.
struct ArmPart {
  Eigen::Vector3d a_mm;
  Eigen::Vector3d b_mm;
  double radius_mm = 0.0;
};

// The calibration light on the tool tip (an LED facing the camera): a bright
// disc drawn over everything, at the tip's image position projected at the
// tip's true height.
struct ToolLight {
  Eigen::Vector3d tip_mm = Eigen::Vector3d::Zero();  // tool tip in F, mm
  double radius_px = 6.0;                            // ~12 px across
  double level = 250.0;                              // grey level before lighting (marks: 240)
};

// How the camera saw one sheep's mark.
struct MarkView {
  int32_t id = 0;
  Eigen::Vector2d centre_px;     // true mark centre in the image (projected at mark height), px
  double radius_px = 0.0;        // mark radius in the image, px
  double hidden_fraction = 0.0;  // of the mark's area, covered by the arm
  bool visible = true;           // hidden_fraction < max_hidden_fraction
};

class CameraRenderer {
 public:
  // `world` gives the sheep's dimensions and the field size.
  CameraRenderer(CameraConfig config, const WorldConfig& world);

  int width() const { return config_.camera.width_px; }
  int height() const { return config_.camera.height_px; }
  const CameraConfig& config() const { return config_; }

  // Renders one frame into `image` (resized to width * height bytes, row-major,
  // row 0 at the top) and returns one view per sheep, in the order given.
  // `light` (may be null): the tool light, drawn last (it is on the tip,
  // facing the camera, so the arm never hides it). `clouds` are between the
  // camera and everything else: drawn over all of it.
  std::vector<MarkView> render(const std::vector<SheepState>& sheep,
                               const std::vector<ArmPart>& arm, std::vector<uint8_t>& image,
                               const ToolLight* light = nullptr,
                               const std::vector<Cloud>& clouds = {});

  // Where each mark is and how much of it the arm hides, without rendering.
  std::vector<MarkView> mark_views(const std::vector<SheepState>& sheep,
                                   const std::vector<ArmPart>& arm) const;

 private:
  struct Capsule2 {  // an arm part in the image
    Eigen::Vector2d a, b;
    double ra, rb;  // px
  };
  Capsule2 project(const ArmPart& part) const;
  static bool covers(const Capsule2& c, const Eigen::Vector2d& p);
  void blend_disc(const Eigen::Vector2d& centre, double radius, double level);
  void blend_convex(const std::vector<Eigen::Vector2d>& poly, double level,
                    std::vector<float>& target) const;
  void blend_capsule(const Capsule2& c, double level);
  void blend_cloud(const Cloud& cloud);

  CameraConfig config_;
  WorldConfig world_;
  std::vector<float> background_;  // grey levels before lighting
  std::vector<float> gain_;
  std::vector<float> scene_;
  std::vector<float> noise_table_;  // N(0, 1) samples
  std::mt19937_64 rng_;
};

}  // namespace ephor::sim
