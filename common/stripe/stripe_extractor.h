#pragma once
// The stripe in a thresholded image (paper 004, section 2): "The connectivity
// algorithm in the vision module has been specially modified for use with
// stripes that run in a generally top-to-bottom orientation. It finds the
// tallest stripe in the image, throwing away spurs and other noise. The image
// coordinates of points at the centerline of the stripe, and the horizontal
// width of the stripe at each point, are made available".
//
// Here: every row's runs of pixels at or above the threshold are the nodes; a
// run links to the runs of the row above that overlap it (within
// max_column_jump_px: 1 is 8-connectivity). The stripe is the longest chain
// of linked runs, one run per row (dynamic programming from the top; ties go
// to the brighter chain), so branches (spurs), blobs and shorter stripes are
// dropped. Each kept row gives a centre (sub-pixel, by the chosen method) and
// the run's width.

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace ephor::stripe {

enum class CentreMethod {
  kRunCentre,  // the paper's: midpoint of the thresholded run (half-pixel steps)
  kCentroid,   // grey-weighted centroid of the run +-2 px above the local background
  kGaussian,   // three-point Gaussian (log-parabola) fit at the run's brightest pixel
  kSteger,     // Steger's line point: Gaussian-derivative Hessian at the brightest
               // pixel gives the line's normal; the zero of the derivative across
               // the line, interpolated along the row (see the .cc)
};

const char* centre_method_name(CentreMethod m);
// "run", "centroid", "gaussian", "steger"; throws std::invalid_argument otherwise.
CentreMethod parse_centre_method(const std::string& name);

struct StripeExtractorOptions {
  int threshold = 60;          // grey level, pixel >= threshold is "on"
  int max_column_jump_px = 1;  // how far apart runs of adjacent rows may be and still link
  int min_rows = 3;            // a stripe shorter than this is "no stripe"
  CentreMethod method = CentreMethod::kGaussian;
  double steger_sigma_px = 1.0;  // Gaussian scale of Steger's derivatives
};

// One row of the stripe.
struct StripePoint {
  int row = 0;            // v, pixels
  double u_px = 0.0;      // centre column, sub-pixel (pixel centres at integers)
  double width_px = 0.0;  // horizontal width of the run (last - first + 1)
  int first_col = 0;      // run's first and last "on" column
  int last_col = 0;
  double peak = 0.0;  // brightest grey level of the run
};

struct Stripe {
  std::vector<StripePoint> points;  // top to bottom, one per row, rows increasing
  int runs_found = 0;               // every run above threshold in the image
  int runs_dropped = 0;             // spurs, noise and other stripes thrown away
  int height_rows() const {
    return points.empty() ? 0 : points.back().row - points.front().row + 1;
  }
};

class StripeExtractor {
 public:
  // Throws std::invalid_argument on a threshold outside 1..255, a negative
  // jump, min_rows < 1 or a non-positive Steger sigma.
  explicit StripeExtractor(StripeExtractorOptions options = {});

  // image: 8-bit single channel (CV_8UC1). Throws std::invalid_argument
  // otherwise. An image without a stripe of min_rows gives no points.
  Stripe extract(const cv::Mat& image) const;

  // The centre of row `row` for the run [first, last] by `method` (exposed for
  // the comparison in the benchmark).
  double centre(const cv::Mat& image, int row, int first, int last, CentreMethod method) const;

  const StripeExtractorOptions& options() const { return options_; }

 private:
  StripeExtractorOptions options_;
};

}  // namespace ephor::stripe
