#include "common/stripe/stripe_extractor.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Eigenvalues>

namespace ephor::stripe {

namespace {

struct Run {
  int first;
  int last;
  double brightness;  // sum of grey levels
};

double px(const cv::Mat& img, int row, int col) {
  col = std::clamp(col, 0, img.cols - 1);
  row = std::clamp(row, 0, img.rows - 1);
  return img.at<unsigned char>(row, col);
}

int brightest(const cv::Mat& img, int row, int first, int last) {
  int best = first;
  for (int c = first + 1; c <= last; ++c)
    if (px(img, row, c) > px(img, row, best)) best = c;
  // Saturated plateaus: take the middle of the equal-maximum stretch.
  int end = best;
  while (end + 1 <= last && px(img, row, end + 1) == px(img, row, best)) ++end;
  return (best + end) / 2;
}

double local_background(const cv::Mat& img, int row, int first, int last) {
  double bg = 255.0;
  for (int c = first - 3; c <= last + 3; ++c) bg = std::min(bg, px(img, row, c));
  return bg;
}

}  // namespace

const char* centre_method_name(CentreMethod m) {
  switch (m) {
    case CentreMethod::kRunCentre:
      return "run";
    case CentreMethod::kCentroid:
      return "centroid";
    case CentreMethod::kGaussian:
      return "gaussian";
    case CentreMethod::kSteger:
      return "steger";
  }
  return "?";
}

CentreMethod parse_centre_method(const std::string& name) {
  for (CentreMethod m : {CentreMethod::kRunCentre, CentreMethod::kCentroid, CentreMethod::kGaussian,
                         CentreMethod::kSteger})
    if (name == centre_method_name(m)) return m;
  throw std::invalid_argument("unknown stripe centre method '" + name +
                              "' (run, centroid, gaussian, steger)");
}

StripeExtractor::StripeExtractor(StripeExtractorOptions options) : options_(options) {
  if (options_.threshold < 1 || options_.threshold > 255)
    throw std::invalid_argument("StripeExtractor: threshold must be 1..255");
  if (options_.max_column_jump_px < 0)
    throw std::invalid_argument("StripeExtractor: max_column_jump_px must be >= 0");
  if (options_.min_rows < 1) throw std::invalid_argument("StripeExtractor: min_rows must be >= 1");
  if (!(options_.steger_sigma_px > 0.0) || !std::isfinite(options_.steger_sigma_px))
    throw std::invalid_argument("StripeExtractor: steger_sigma_px must be > 0");
}

double StripeExtractor::centre(const cv::Mat& img, int row, int first, int last,
                               CentreMethod method) const {
  const double run_centre = 0.5 * (first + last);
  switch (method) {
    case CentreMethod::kRunCentre:
      return run_centre;
    case CentreMethod::kCentroid: {
      const double bg = local_background(img, row, first, last);
      double sw = 0.0, swx = 0.0;
      for (int c = first - 2; c <= last + 2; ++c) {
        if (c < 0 || c >= img.cols) continue;
        const double w = px(img, row, c) - bg;
        sw += w;
        swx += w * c;
      }
      return sw > 0.0 ? swx / sw : run_centre;
    }
    case CentreMethod::kGaussian: {
      const int p = brightest(img, row, first, last);
      if (p <= 0 || p >= img.cols - 1) return run_centre;
      const double bg = local_background(img, row, first, last);
      const double a = std::log(std::max(px(img, row, p - 1) - bg, 0.5));
      const double b = std::log(std::max(px(img, row, p) - bg, 0.5));
      const double c = std::log(std::max(px(img, row, p + 1) - bg, 0.5));
      const double den = a - 2.0 * b + c;
      if (!(den < 0.0)) return run_centre;
      const double d = 0.5 * (a - c) / den;
      return std::abs(d) <= 1.0 ? p + d : run_centre;
    }
    case CentreMethod::kSteger: {
      const double s = options_.steger_sigma_px;
      const int r = static_cast<int>(std::ceil(3.0 * s));
      // Within the smoothing radius of the top or bottom edge the window
      // would see the edge row repeated (a vertical stub, biased by the
      // stripe's slope): the Gaussian fit needs only the row itself.
      if (row < r || row >= img.rows - r)
        return centre(img, row, first, last, CentreMethod::kGaussian);
      const int p = brightest(img, row, first, last);
      // Gaussian and its first two derivatives, sampled (unnormalised is fine
      // for g'/g'' ratios but the mixed terms need consistent scales).
      std::vector<double> g(2 * r + 1), g1(2 * r + 1), g2(2 * r + 1);
      double norm = 0.0;
      for (int i = -r; i <= r; ++i) norm += std::exp(-0.5 * i * i / (s * s));
      for (int i = -r; i <= r; ++i) {
        const double e = std::exp(-0.5 * i * i / (s * s)) / norm;
        g[i + r] = e;
        g1[i + r] = -i / (s * s) * e;
        g2[i + r] = (i * i / (s * s) - 1.0) / (s * s) * e;
      }
      struct Derivs {
        double g = 0, dx = 0, dy = 0, dxx = 0, dyy = 0, dxy = 0;
      };
      auto derivs = [&](int v, int u) {
        Derivs d;
        for (int j = -r; j <= r; ++j) {
          for (int i = -r; i <= r; ++i) {
            // Convolution with the derivative kernels: (f * g')(u) = sum f(u - i) g'(i).
            const double f = px(img, v - j, u - i);
            d.g += f * g[i + r] * g[j + r];
            d.dx += f * g1[i + r] * g[j + r];
            d.dy += f * g[i + r] * g1[j + r];
            d.dxx += f * g2[i + r] * g[j + r];
            d.dyy += f * g[i + r] * g2[j + r];
            d.dxy += f * g1[i + r] * g1[j + r];
          }
        }
        return d;
      };
      const Derivs d0 = derivs(row, p);
      Eigen::Matrix2d h;
      h << d0.dxx, d0.dxy, d0.dxy, d0.dyy;
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(h);
      // The line's normal: the direction of the most negative curvature.
      const int k = es.eigenvalues()[0] < es.eigenvalues()[1] ? 0 : 1;
      const Eigen::Vector2d n = es.eigenvectors().col(k);
      if (!(es.eigenvalues()[k] < 0.0) || std::abs(n.x()) < 0.2) return run_centre;
      // Steger's line point is where the derivative across the line (along
      // n) vanishes. His single Taylor step from the pixel is off by up to
      // ~0.08 px for a 2 px wide stripe half a pixel away (the smoothed
      // profile is far from a parabola there). Instead the zero is
      // interpolated linearly between the row's two pixels that bracket it,
      // on the derivative divided by the smoothed grey level above the
      // background: for a Gaussian profile that ratio (the log-derivative) is
      // exactly linear across the line.
      const double bg = local_background(img, row, first, last);
      auto ratio = [&](int u) {
        const Derivs d = u == p ? d0 : derivs(row, u);
        return (n.x() * d.dx + n.y() * d.dy) / std::max(d.g - bg, 1e-6);
      };
      const double rc = ratio(p);
      int lo = p;
      double rlo = rc, rhi = ratio(p + 1);
      if (rlo * rhi > 0.0) {
        lo = p - 1;
        rlo = ratio(p - 1);
        rhi = rc;
      }
      if (rlo * rhi > 0.0 || rlo == rhi) return run_centre;
      const double x = lo + rlo / (rlo - rhi) - p;
      return std::abs(x) <= 1.0 ? p + x : run_centre;
    }
  }
  return run_centre;
}

Stripe StripeExtractor::extract(const cv::Mat& image) const {
  if (image.empty() || image.type() != CV_8UC1)
    throw std::invalid_argument("StripeExtractor: image must be a non-empty 8-bit grey image");
  Stripe out;
  const int rows = image.rows, cols = image.cols;
  const int thr = options_.threshold;
  std::vector<std::vector<Run>> runs(rows);
  for (int r = 0; r < rows; ++r) {
    const unsigned char* p = image.ptr<unsigned char>(r);
    for (int c = 0; c < cols;) {
      if (p[c] < thr) {
        ++c;
        continue;
      }
      Run run{c, c, 0.0};
      while (c < cols && p[c] >= thr) {
        run.brightness += p[c];
        run.last = c++;
      }
      runs[r].push_back(run);
    }
    out.runs_found += static_cast<int>(runs[r].size());
  }
  // Longest chain ending at each run; ties to the brighter chain.
  struct Node {
    int length = 0;
    double brightness = 0.0;
    int prev = -1;  // index in the previous row's runs
  };
  std::vector<std::vector<Node>> dp(rows);
  int best_row = -1, best_idx = -1;
  const int jump = options_.max_column_jump_px;
  for (int r = 0; r < rows; ++r) {
    dp[r].resize(runs[r].size());
    for (size_t i = 0; i < runs[r].size(); ++i) {
      const Run& b = runs[r][i];
      Node n{1, b.brightness, -1};
      if (r > 0) {
        for (size_t j = 0; j < runs[r - 1].size(); ++j) {
          const Run& a = runs[r - 1][j];
          if (a.first > b.last + jump || b.first > a.last + jump) continue;
          const Node& m = dp[r - 1][j];
          if (m.length + 1 > n.length ||
              (m.length + 1 == n.length && m.brightness + b.brightness > n.brightness)) {
            n = Node{m.length + 1, m.brightness + b.brightness, static_cast<int>(j)};
          }
        }
      }
      dp[r][i] = n;
      if (best_row < 0 || n.length > dp[best_row][best_idx].length ||
          (n.length == dp[best_row][best_idx].length &&
           n.brightness > dp[best_row][best_idx].brightness)) {
        best_row = r;
        best_idx = static_cast<int>(i);
      }
    }
  }
  if (best_row < 0 || dp[best_row][best_idx].length < options_.min_rows) {
    out.runs_dropped = out.runs_found;
    return out;
  }
  out.points.resize(dp[best_row][best_idx].length);
  int r = best_row, idx = best_idx;
  for (int k = static_cast<int>(out.points.size()) - 1; k >= 0; --k, --r) {
    const Run& run = runs[r][idx];
    StripePoint& sp = out.points[k];
    sp.row = r;
    sp.first_col = run.first;
    sp.last_col = run.last;
    sp.width_px = run.last - run.first + 1;
    sp.peak = px(image, r, brightest(image, r, run.first, run.last));
    sp.u_px = centre(image, r, run.first, run.last, options_.method);
    idx = dp[r][idx].prev;
  }
  out.runs_dropped = out.runs_found - static_cast<int>(out.points.size());
  return out;
}

}  // namespace ephor::stripe
