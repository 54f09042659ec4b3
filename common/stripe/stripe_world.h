#pragma once
// The simulated world of the light-stripe system: the scene on the table, the
// arm as it really is (TrueArm) and the cage as it really is (the true C_T,
// S_T and P). Given joint readings it renders the camera's image; nothing
// else leaves it (the software never sees the truth).

#include <cstdint>

#include <opencv2/core.hpp>

#include "common/stripe/scan_geometry.h"
#include "common/stripe/stripe_renderer.h"
#include "common/stripe/true_arm.h"

namespace ephor::stripe {

// What --robot-seed draws: the arm's and the cage's true errors.
struct RobotTruth {
  TrueArm arm;
  SensorCalibration cage;

  // No errors: the nominal arm and the drawing cage.
  static RobotTruth ideal();
  // ArmErrors::draw(seed) and the drawing cage with each of the camera and
  // the projector moved up to cage_mm along each axis and turned up to
  // cage_deg about a random axis.
  static RobotTruth draw(std::uint64_t seed, double cage_mm = 3.0, double cage_deg = 2.0);
};

class StripeWorld {
 public:
  // `scene` must outlive the world.
  StripeWorld(const StripeScene& scene, StripeWorkcell cell, RobotTruth truth,
              StripeRendererOptions options = {});

  // The true flange pose in the table frame for joint readings q.
  Eigen::Isometry3d flange_in_table(const arm::Joints& q) const;
  // The camera's image at joint readings q (seeded noise).
  cv::Mat image(const arm::Joints& q, std::uint64_t seed) const;

  // The image with the infrared filter removed and the laser off.
  cv::Mat spot_image(const arm::Joints& q, std::uint64_t seed) const;

  const StripeScene& scene() const { return *scene_; }
  const StripeWorkcell& cell() const { return cell_; }
  const RobotTruth& truth() const { return truth_; }
  const StripeRenderer& renderer() const { return renderer_; }

 private:
  const StripeScene* scene_;
  StripeWorkcell cell_;
  RobotTruth truth_;
  StripeRenderer renderer_;
};

}  // namespace ephor::stripe
