// Fuzz target (issue 18): a STRIPE_IMAGE message as the light-stripe
// system's processes take it: the bytes decoded as stripe_image_t the way the
// bus does (a message that does not decode to its full size is dropped);
// then, as ephor-stripe-stripe's extract task does with a MODE_STRIPE image,
// image_of() (sizes that disagree with the data, non-finite joints refused),
// the StripeExtractor with the centre method and threshold the message's
// image_index picks (all four methods over a corpus), profile_of() for the
// profile it publishes; and, as ephor-stripe-calibrate does with a MODE_SPOT
// image (it takes any mode), find_spot(). The profile must encode and decode to its own size and
// read back through stripe_of() (what ephor-stripe-range does with it) with
// the same rows; a found spot must lie inside the image.
// Seeds: fuzz_corpus/stripe_image (a stripe and a spot image, small).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/fuzz/fuzz_input.h"
#include "common/stripe/sensor_calibrator.h"
#include "common/stripe/stripe_extractor.h"
#include "common/stripe/stripe_messages.h"
#include "ephor/stripe_capture_t.hpp"
#include "ephor/stripe_image_t.hpp"
#include "ephor/stripe_profile_t.hpp"

namespace {

using namespace ephor;
using namespace ephor::stripe;

void stripe_process(const stripe_image_t& m, const cv::Mat& image) {
  static const CentreMethod kMethods[] = {CentreMethod::kRunCentre, CentreMethod::kCentroid,
                                          CentreMethod::kGaussian, CentreMethod::kSteger};
  StripeExtractorOptions options;
  const auto pick = static_cast<uint64_t>(m.image_index);
  options.method = kMethods[pick % 4];
  options.threshold = 1 + static_cast<int>((pick / 4) % 255);  // --threshold's range, 1..255
  const StripeExtractor extractor(options);
  const Stripe stripe = extractor.extract(image);
  const stripe_profile_t p = profile_of(m, stripe, options);

  // What the bus sends and the range process reads back.
  const int size = p.getEncodedSize();
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  if (p.encode(bytes.data(), 0, size) != size) fuzz::fail("the profile does not encode");
  stripe_profile_t back;
  if (back.decode(bytes.data(), 0, size) != size) fuzz::fail("the profile does not decode");
  std::string why;
  const Stripe read = stripe_of(back, &why);
  if (!why.empty()) fuzz::fail("the range process refuses the stripe process's profile: " + why);
  if (read.points.size() != stripe.points.size())
    fuzz::fail("the profile lost rows on the way to the range process");
  for (const StripePoint& s : stripe.points)
    if (s.row < 0 || s.row >= image.rows || !(s.u_px >= -1.0 && s.u_px <= image.cols) ||
        !std::isfinite(s.width_px))
      fuzz::fail("a stripe point outside the image or not finite");
}

void calibrate_process(const cv::Mat& image) {
  const auto spot = find_spot(image);
  if (spot && !(spot->x() >= 0.0 && spot->x() <= image.cols - 1 && spot->y() >= 0.0 &&
                spot->y() <= image.rows - 1))
    fuzz::fail("a spot outside the image");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 1 << 20) return 0;  // larger than the images here
  stripe_image_t m;
  const int n = static_cast<int>(size);
  if (m.decode(data, 0, n) != n) return 0;
  std::string why;
  const cv::Mat image = image_of(m, &why);
  if (image.empty()) {
    if (why.empty()) fuzz::fail("an image refused without a reason");
    return 0;
  }
  // The stripe process skips any image but MODE_STRIPE; the calibration
  // process takes what it asked for, whatever the mode says.
  if (m.mode == stripe_capture_t::MODE_STRIPE) stripe_process(m, image);
  calibrate_process(image);
  return 0;
}
