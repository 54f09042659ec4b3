#include "common/stripe/range_finder.h"

namespace ephor::stripe {

RangeFinder::RangeFinder(StripeWorkcell cell, TrueArm arm_model, SensorCalibration calibration,
                         StripeExtractorOptions extractor)
    : cell_(cell), arm_(std::move(arm_model)), calibration_(calibration), extractor_(extractor) {}

Eigen::Isometry3d RangeFinder::flange_in_table(const arm::Joints& q) const {
  return cell_.base_in_table * arm_.flange(q);
}

Collineation RangeFinder::collineation(const arm::Joints& q) const {
  return Collineation::from_flange(flange_in_table(q), calibration_);
}

std::vector<RangePoint> RangeFinder::to_table(const Stripe& stripe, const arm::Joints& q) const {
  const Collineation k = collineation(q);
  std::vector<RangePoint> out;
  out.reserve(stripe.points.size());
  for (const StripePoint& sp : stripe.points) {
    const auto p = k.to_world(sp.u_px, sp.row);
    if (!p) continue;
    out.push_back(RangePoint{*p, sp.row, sp.u_px, sp.width_px});
  }
  return out;
}

std::vector<RangePoint> RangeFinder::measure(const cv::Mat& image, const arm::Joints& q,
                                             Stripe* stripe_out) const {
  Stripe s = extractor_.extract(image);
  std::vector<RangePoint> pts = to_table(s, q);
  if (stripe_out) *stripe_out = std::move(s);
  return pts;
}

}  // namespace ephor::stripe
