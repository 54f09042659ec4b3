#pragma once
// The software side of paper 004's sensor (the `stripe` and `range`
// processes' core): an image and the joint readings it was taken at in, 3-D
// points of the stripe in the table frame out. It knows only the nominal
// arm (or the zero references a calibration found), the work cell and the
// calibration file's C_T, S_T and P.

#include <vector>

#include <opencv2/core.hpp>

#include "common/stripe/collineation.h"
#include "common/stripe/scan_geometry.h"
#include "common/stripe/stripe_extractor.h"
#include "common/stripe/true_arm.h"

namespace ephor::stripe {

struct RangePoint {
  Eigen::Vector3d table_mm;  // the point, mm, table frame
  int row = 0;               // image row of the stripe point
  double u_px = 0.0;         // its sub-pixel column
  double width_px = 0.0;     // the stripe's horizontal width there
};

class RangeFinder {
 public:
  RangeFinder(StripeWorkcell cell, TrueArm arm_model, SensorCalibration calibration,
              StripeExtractorOptions extractor = {});

  // The flange in the table frame as the software believes it.
  Eigen::Isometry3d flange_in_table(const arm::Joints& q) const;
  // K for joint readings q (table frame).
  Collineation collineation(const arm::Joints& q) const;

  // Stripe points to 3-D (those whose rays meet the light plane in front).
  std::vector<RangePoint> to_table(const Stripe& stripe, const arm::Joints& q) const;
  // Extraction then to_table.
  std::vector<RangePoint> measure(const cv::Mat& image, const arm::Joints& q,
                                  Stripe* stripe_out = nullptr) const;

  const SensorCalibration& calibration() const { return calibration_; }
  const TrueArm& arm_model() const { return arm_; }
  const StripeExtractor& extractor() const { return extractor_; }

 private:
  StripeWorkcell cell_;
  TrueArm arm_;
  SensorCalibration calibration_;
  StripeExtractor extractor_;
};

}  // namespace ephor::stripe
