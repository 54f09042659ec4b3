#pragma once
// Clouds (paper 003, section 6, the "clouds" class variation: "multiple
// clouds throughout the field ... frequently obscured sheep"): soft-edged
// shapes between the camera and the field, some darker and some brighter
// than the field, drifting across the image and wrapping round its edges.
//
// Each cloud is an ellipse in the image (px) with an opaque core and a soft
// edge: a pixel under it is blended toward the cloud's grey level with
// weight opacity * s(d), where d is the elliptical distance from the centre
// (1 at the edge) and s falls smoothly from 1 at d = core to 0 at d = 1. A
// mark under a core is hidden; under an edge it is dimmed and partly hidden,
// as the arm hides it. The clouds' motion is a function of time only, so a
// replayed time gives the same clouds.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace ephor::sim {

struct Cloud {
  Eigen::Vector2d centre_px;  // image, px (u right, v down)
  double semi_u_px = 60.0;    // semi-axes, px (axis-aligned before rotation)
  double semi_v_px = 40.0;
  double angle_rad = 0.0;  // rotation of the u semi-axis from the image u axis
  double level = 10.0;     // grey level the cloud blends toward, 0..255
  double opacity = 0.95;   // blend weight in the core, [0, 1]
  double core = 0.5;       // elliptical distance where the soft edge starts, [0, 1)

  // The blend weight at image point p, [0, opacity].
  double weight(const Eigen::Vector2d& p) const;
};

struct CloudFieldConfig {
  int clouds = 0;
  uint64_t seed = 1;
  // Drawn per cloud, uniformly: semi-axes, speed. The defaults hide a sheep's
  // mark for a few seconds as a cloud passes (the world model dead-reckons an
  // obscured object for up to 10 s).
  double min_semi_px = 35.0;
  double max_semi_px = 70.0;
  double min_speed_px_s = 12.0;
  double max_speed_px_s = 25.0;
  double dark_level = 10.0;    // darker than the field (40)
  double bright_level = 95.0;  // brighter than the field, below the marks' threshold
};

class CloudField {
 public:
  // Clouds alternate dark and bright; they start spread over the image.
  CloudField(const CloudFieldConfig& config, int width_px, int height_px);

  // The clouds at simulated time t (s): each drifts in a straight line and
  // wraps round the image with a margin, so it leaves one edge whole and comes
  // back whole at the other.
  std::vector<Cloud> at(double t_s) const;

  int size() const { return static_cast<int>(start_.size()); }

 private:
  std::vector<Cloud> start_;
  std::vector<Eigen::Vector2d> velocity_px_s_;
  int width_px_;
  int height_px_;
};

// Throws std::invalid_argument naming the first bad field.
void validate(const CloudFieldConfig& config);

}  // namespace ephor::sim
