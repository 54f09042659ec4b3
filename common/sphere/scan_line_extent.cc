#include "common/sphere/scan_line_extent.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <string>

#include <Eigen/Dense>

namespace ephor::sphere {

ScanLineExtentConfig ScanLineExtentConfig::improved() {
  ScanLineExtentConfig c;
  c.edge_correction = true;
  c.exact_geometry = true;
  c.weighted_regression = true;
  c.profile_sign = true;
  c.window_slope = true;
  c.iterations = 2;
  return c;
}

LineFit regress(const std::vector<double>& t, const std::vector<double>& x,
                const std::vector<double>* weights) {
  // Equations 39-40, written about the (weighted) mean time for round-off.
  double sw = 0.0, st = 0.0, sx = 0.0;
  for (size_t j = 0; j < t.size(); ++j) {
    const double w = weights ? (*weights)[j] : 1.0;
    sw += w;
    st += w * t[j];
    sx += w * x[j];
  }
  LineFit fit;
  if (sw <= 0.0) return fit;
  const double tm = st / sw, xm = sx / sw;
  double stt = 0.0, stx = 0.0;
  for (size_t j = 0; j < t.size(); ++j) {
    const double w = weights ? (*weights)[j] : 1.0;
    stt += w * (t[j] - tm) * (t[j] - tm);
    stx += w * (t[j] - tm) * (x[j] - xm);
  }
  fit.slope = stt > 1e-18 ? stx / stt : 0.0;
  fit.x0 = xm - fit.slope * tm;
  return fit;
}

namespace {

// sin and cos of the small angles within a scan line's chord (|a| < 0.1 rad
// at 1 m): Taylor series accurate to 1e-13 below 0.2 rad, five times faster
// than the library calls that dominated the per-point loop.
// Below 0.03 rad (every angle at 10 m and beyond) three terms reach the same
// accuracy: the dependent multiply-adds were a third of the time at 20 m.
inline double small_sin(double a) {
  constexpr double k3 = 1.0 / 6, k5 = 1.0 / 120, k7 = 1.0 / 5040, k9 = 1.0 / 362880;
  const double a2 = a * a;
  if (a2 < 0.03 * 0.03) return a * (1.0 - a2 * (k3 - a2 * (k5 - a2 * k7)));
  if (a2 > 0.2 * 0.2) return std::sin(a);
  return a * (1.0 - a2 * (k3 - a2 * (k5 - a2 * (k7 - a2 * k9))));
}
inline double small_cos(double a) {
  constexpr double k2 = 0.5, k4 = 1.0 / 24, k6 = 1.0 / 720, k8 = 1.0 / 40320, k10 = 1.0 / 3628800;
  const double a2 = a * a;
  if (a2 < 0.03 * 0.03) return 1.0 - a2 * (k2 - a2 * (k4 - a2 * k6));
  if (a2 > 0.2 * 0.2) return std::cos(a);
  return 1.0 - a2 * (k2 - a2 * (k4 - a2 * (k6 - a2 * (k8 - a2 * k10))));
}
inline double small_atan(double x) {
  if (std::abs(x) > 0.1) return std::atan(x);
  constexpr double k3 = 1.0 / 3, k5 = 1.0 / 5, k7 = 1.0 / 7, k9 = 1.0 / 9, k11 = 1.0 / 11;
  const double x2 = x * x;
  return x * (1.0 - x2 * (k3 - x2 * (k5 - x2 * (k7 - x2 * (k9 - x2 * k11)))));
}

// The azimuth step between pulses: each line's mean step (its azimuth span
// over its pulse count; encoder noise enters as sigma sqrt(2) / (n - 1)),
// the median over the lines.
double azimuth_step(const Window& window) {
  // At most 64 lines, spread over the window: the step is the scanner's
  // (constant over a window), so more lines only cost time.
  thread_local std::vector<double> steps;
  steps.clear();
  const size_t stride = std::max<size_t>(1, window.lines.size() / 64);
  for (size_t j = 0; j < window.lines.size(); j += stride) {
    const ScanLine& line = window.lines[j];
    const size_t n = line.pulses.size();
    if (n < 3) continue;
    steps.push_back(std::abs(line.pulses[n - 1].azimuth_rad - line.pulses[0].azimuth_rad) /
                    static_cast<double>(n - 1));
  }
  if (steps.empty()) return 0.0;
  const auto mid = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
  std::nth_element(steps.begin(), mid, steps.end());
  return *mid;
}

// The alignment of eq. 12-13 for a slope of elevation on azimuth: theta =
// atan(slope) with its cosine and sine (once per window and scan direction
// when the slope is the window's; per line for the paper's own fits).
struct Alignment {
  double slope = 0.0;
  double ct = 1.0, st = 0.0;  // cos and sin of theta, without the library calls
  double theta = 0.0;
  static Alignment of_slope(double slope) {
    Alignment a;
    a.slope = slope;
    a.ct = 1.0 / std::sqrt(1.0 + slope * slope);
    a.st = slope * a.ct;
    a.theta = small_atan(slope);
    return a;
  }
};

// The slope of elevation on azimuth of the window's lines, per scan
// direction (index 0: azimuth increasing, 1: decreasing): the sums of the
// lines' end-to-end changes, over at most 128 lines of each direction spread
// over the window. Unset for a direction without lines.
struct WindowSlope {
  Alignment by_direction[2];
  bool known[2] = {false, false};
  // The alignment for `line`, or nullptr when its direction had no lines.
  const Alignment* of(const ScanLine& line) const {
    const size_t n = line.pulses.size();
    const int dir = n < 2 || line.pulses[n - 1].azimuth_rad >= line.pulses[0].azimuth_rad ? 0 : 1;
    return known[dir] ? &by_direction[dir] : nullptr;
  }
};

WindowSlope window_slope(const Window& window) {
  double de[2] = {0.0, 0.0}, da[2] = {0.0, 0.0};
  const size_t stride = std::max<size_t>(1, window.lines.size() / 128);
  for (size_t j = 0; j < window.lines.size(); j += stride) {
    const std::vector<Pulse>& p = window.lines[j].pulses;
    if (p.size() < 2) continue;
    const double d_az = p.back().azimuth_rad - p.front().azimuth_rad;
    const int dir = d_az >= 0.0 ? 0 : 1;
    da[dir] += d_az;
    de[dir] += p.back().elevation_rad - p.front().elevation_rad;
  }
  WindowSlope w;
  for (int dir = 0; dir < 2; ++dir) {
    if (da[dir] == 0.0) continue;
    w.by_direction[dir] = Alignment::of_slope(de[dir] / da[dir]);
    w.known[dir] = true;
  }
  return w;
}

struct Rejections {
  int at_edge = 0;
  int too_few = 0;
};

// Per-point work arrays, reused over the lines of a window (no allocation
// per line once they have grown to the longest line).
struct LineScratch {
  std::vector<double> dd, xx, w;
};

// One line's estimate before its sign is chosen (eq. 12-28). What depends
// only on the configuration and the window (the pulse step, the noise
// terms, the window's alignments) is worked out once per window here, not
// once per line.
class LineSolver {
 public:
  LineSolver(const ScanLineExtentConfig& cfg, double delta, const WindowSlope* slopes)
      : cfg_(cfg),
        slopes_(slopes),
        delta_(cfg.edge_correction ? delta : 0.0),
        sig_lambda2_(2.0 * cfg.angle_sigma_rad * cfg.angle_sigma_rad +
                     (cfg.edge_correction ? delta * delta / 6.0 : 0.0)),
        sig_lambda_(std::sqrt(sig_lambda2_)),
        sr2_(cfg.range_sigma_m * cfg.range_sigma_m),
        sa2_(cfg.angle_sigma_rad * cfg.angle_sigma_rad),
        quant_(cfg.edge_correction ? delta * delta / 12.0 : 0.0),
        iterations_(std::max(1, cfg.iterations)) {}

  // Writes the line's estimate into `e`; false (and the reason counted)
  // when the line is not usable. `hits`: the line's foreground pulses.
  bool solve(const ScanLine& line, size_t index, std::span<const size_t> hits, Rejections& rejected,
             LineScratch& scratch, LineExtent& e) const;

 private:
  const ScanLineExtentConfig& cfg_;
  const WindowSlope* slopes_;        // nullptr: each line fits its own (the paper's)
  double delta_;                     // the edge correction added to the extent, rad
  double sig_lambda2_, sig_lambda_;  // the extent's variance (rad^2) and sigma
  double sr2_, sa2_;                 // range (m^2) and angle (rad^2) variances
  double quant_;                     // the pulse spacing's quantisation variance, rad^2
  int iterations_;
};

bool LineSolver::solve(const ScanLine& line, size_t index, std::span<const size_t> hits,
                       Rejections& rejected, LineScratch& scratch, LineExtent& e) const {
  const ScanLineExtentConfig& cfg = cfg_;
  if (hits.empty()) return false;
  // Section 3: a line whose edge of the sphere cannot be found (the sphere
  // cut by the frame's side, or the line cut by the window) is useless.
  if (hits.front() == 0 || hits.back() + 1 == line.pulses.size()) {
    ++rejected.at_edge;
    return false;
  }
  const int m = static_cast<int>(hits.size());
  if (m < cfg.min_points_per_line) {
    ++rejected.too_few;
    return false;
  }
  const double inv_m = 1.0 / m;
  // Every field of `e` is written here or in finish(): no reset (a zeroing
  // of the whole struct per line showed in the profile).
  e.line_index = index;
  e.points = m;
  const Pulse& first = line.pulses[hits.front()];
  const Pulse& last = line.pulses[hits.back()];
  e.t_s = 0.5 * (first.t_s + last.t_s);  // eq. 34

  // Eq. 12-13: align the line with the azimuth axis. The slope theta of
  // elevation on azimuth; we rotate by -theta (the printed +theta doubles
  // the slope), eq. 32-33 rotate back. The window's slope, or the line's own
  // from one pass of sums about the first point (small numbers: no
  // cancellation).
  const Alignment* known = slopes_ ? slopes_->of(line) : nullptr;
  Alignment own;
  if (!known) {
    double slope = 0.0;
    if (m >= 3) {
      double sa = 0.0, se = 0.0, saa = 0.0, sae = 0.0;
      for (size_t i : hits) {
        const double da = line.pulses[i].azimuth_rad - first.azimuth_rad;
        const double de = line.pulses[i].elevation_rad - first.elevation_rad;
        sa += da;
        se += de;
        saa += da * da;
        sae += da * de;
      }
      const double var = saa - sa * sa * inv_m;
      if (var > 0.0) slope = (sae - sa * se * inv_m) / var;
    }
    own = Alignment::of_slope(slope);
    known = &own;
  }
  const double ct = known->ct, st = known->st;
  const auto aligned_azimuth = [&](const Pulse& p) {
    return p.azimuth_rad * ct + p.elevation_rad * st;
  };
  const double a_first = aligned_azimuth(first), a_last = aligned_azimuth(last);
  const double mid = 0.5 * (a_first + a_last);  // eq. 15
  // Full extent between the edges (eq. 19 without its halving; see header).
  const double lambda = std::abs(a_last - a_first) + delta_;
  const double half = 0.5 * lambda;
  const double chord_factor =
      cfg.exact_geometry ? small_sin(half) : small_sin(half) / small_cos(half);

  // Eq. 20-26: s_0 from the ends' ranges, then s_k, l_k. The first
  // iteration shares its pass with eq. 15-16 and 23-24 (d_i, x_i and the
  // line's elevation phi in the aligned space), which keep d_i and x_i for
  // any further iteration.
  std::vector<double>&dd = scratch.dd, &xx = scratch.xx, &wt = scratch.w;
  if (dd.size() < hits.size()) {  // grow only: a resize per line zero-fills
    dd.resize(hits.size());
    xx.resize(hits.size());
    wt.resize(hits.size());
  }
  double s = std::max(first.range_m, last.range_m);
  double l = s * chord_factor;  // eq. 22
  double zsens = 0.0;           // mean l / z_i: how s moves with l (for the z variance)
  double phi = 0.0, sum = 0.0, wsum = 0.0;
  {
    const double sig_l2 = 0.25 * s * s * sig_lambda2_;
    for (size_t k = 0; k < hits.size(); ++k) {
      const Pulse& p = line.pulses[hits[k]];
      const double ai = aligned_azimuth(p) - mid;  // eq. 15
      phi += -p.azimuth_rad * st + p.elevation_rad * ct;
      const double r = p.range_m;
      const double d = r * small_cos(ai);  // eq. 23
      const double x = r * small_sin(ai);  // eq. 24
      dd[k] = d;
      xx[k] = x;
      const double z = std::sqrt(std::max(0.0, l * l - x * x));  // eq. 25
      double w = 1.0;
      if (cfg.weighted_regression) {
        // Set once, from s_0: the weights only need to be roughly right, and
        // later iterations then cost a square root per point, not a division
        // (s_0 is within the range noise of s at every distance).
        // 1 / var(d + z): range noise, x noise through dz/dx = -x/z, l noise
        // through dz/dl = l/z (z floored: the chord's very ends):
        // w = zf^2 / den. With q = 1 / (zf den) one division gives both w =
        // zf^3 q and l / zf = l den q.
        const double zf = std::max(z, 0.05 * l);
        const double zf2 = zf * zf;
        const double den = sr2_ * zf2 + x * x * r * r * sa2_ + l * l * sig_l2;
        const double q = 1.0 / (zf * den);
        w = zf2 * zf * q;
        zsens += std::min(l * den * q, 1.0 / 0.3);
      }
      wt[k] = w;
      sum += w * (d + z);
      wsum += w;
    }
  }
  phi *= inv_m;
  for (int k = 0;; ++k) {
    const double s_before = s;
    s = sum / wsum;  // eq. 26
    // Stop when the slice radius would move less than the tolerance (at
    // 10 m and beyond one pass is enough: l is s times a small angle).
    if (k + 1 >= iterations_ || std::abs(s - s_before) * chord_factor < cfg.iteration_tolerance_m) {
      break;
    }
    l = s * chord_factor;  // eq. 22
    sum = 0.0;
    for (size_t i = 0; i < hits.size(); ++i) {
      sum += wt[i] * (dd[i] + std::sqrt(std::max(0.0, l * l - xx[i] * xx[i])));  // eq. 25-26
    }
  }
  zsens *= inv_m;
  const double u = cfg.sphere_radius_m;
  e.theta_rad = known->theta;
  e.cos_theta = ct;
  e.sin_theta = st;
  e.phi_rad = phi;
  e.mid_azimuth_rad = mid;
  e.lambda_rad = lambda;
  e.s_m = s;
  e.l_m = l;
  e.y_abs_m = std::sqrt(std::max(0.0, u * u - l * l));  // eq. 28

  // Variances for the weighted regression (sensor noise propagated).
  const double sig_l = 0.5 * s * sig_lambda_;
  e.variance_m2.x() = 0.5 * s * s * (sa2_ + quant_);
  e.variance_m2.y() =
      s * s * sa2_ * inv_m + sig_l * sig_l * l * l / (e.y_abs_m * e.y_abs_m + sig_l * u);
  e.variance_m2.z() = sr2_ * inv_m + zsens * zsens * sig_l * sig_l;
  return true;
}

// Completes a line's estimate once its sign is chosen: eq. 27-37.
void finish(const ScanLineExtentConfig& cfg, LineExtent& e) {
  const double e_off = e.sign * small_atan(e.y_abs_m / e.s_m);  // eq. 29
  e.range_m =
      cfg.exact_geometry
          ? std::sqrt(e.s_m * e.s_m + e.y_abs_m * e.y_abs_m)  // the centre off the line's plane
          : e.s_m * small_cos(e_off);                         // eq. 27 as printed
  const double a_dot = e.mid_azimuth_rad;                     // eq. 18, 30
  const double e_dot = e_off + e.phi_rad;                     // eq. 31
  const double ct = e.cos_theta, st = e.sin_theta;
  e.azimuth_rad = a_dot * ct - e_dot * st;  // eq. 32-33 (inverse of our eq. 12-13)
  e.elevation_rad = a_dot * st + e_dot * ct;
  const double ca = small_cos(e.azimuth_rad), sa = small_sin(e.azimuth_rad);
  const double ce = small_cos(e.elevation_rad), se = small_sin(e.elevation_rad);
  e.position_m = {e.range_m * sa * ce, e.range_m * se, e.range_m * ca * ce};  // eq. 35-37
}

// Eq. 28-29's sign for each line of one pass over the sphere (a run of
// consecutive lines with returns): lines above the reference are above the
// centre (sign -1), lines below it are below (+1).
void choose_signs(const ScanLineExtentConfig& cfg, std::span<LineExtent> pass) {
  if (pass.empty()) return;
  // The paper's reference: the longest line.
  const LineExtent* longest = &pass.front();
  for (const LineExtent& e : pass) {
    if (e.lambda_rad > longest->lambda_rad) longest = &e;
  }
  double reference = longest->phi_rad;
  bool from_profile = false;
  if (cfg.profile_sign && pass.size() >= 5) {
    // l^2 = u^2 - (s (phi - E_c))^2 is a parabola in phi peaking at the
    // centre's elevation E_c: fit it over the pass.
    // Normal equations in dp scaled to about one (3 x 3, no allocation; the
    // scaling keeps them well conditioned).
    const double p0 = longest->phi_rad;
    double scale = 0.0;
    for (const LineExtent& e : pass) scale = std::max(scale, std::abs(e.phi_rad - p0));
    scale = scale > 0.0 ? scale : 1.0;
    // Power sums of q and q^k l^2 (the normal matrix is a Hankel matrix).
    double sq[5] = {0, 0, 0, 0, 0}, sb[3] = {0, 0, 0};
    const double inv_scale = 1.0 / scale;
    for (const LineExtent& e : pass) {
      const double q = (e.phi_rad - p0) * inv_scale, q2 = q * q;
      const double b = e.l_m * e.l_m;
      sq[0] += 1.0;
      sq[1] += q;
      sq[2] += q2;
      sq[3] += q2 * q;
      sq[4] += q2 * q2;
      sb[0] += b;
      sb[1] += b * q;
      sb[2] += b * q2;
    }
    Eigen::Matrix3d ata;
    ata << sq[0], sq[1], sq[2], sq[1], sq[2], sq[3], sq[2], sq[3], sq[4];
    Eigen::Vector3d c = ata.ldlt().solve(Eigen::Vector3d(sb[0], sb[1], sb[2]));
    c(1) /= scale;
    c(2) /= scale * scale;
    if (c(2) < 0.0) {
      const double peak = p0 - c(1) / (2.0 * c(2));
      double lo = pass.front().phi_rad, hi = lo;
      for (const LineExtent& e : pass) {
        lo = std::min(lo, e.phi_rad);
        hi = std::max(hi, e.phi_rad);
      }
      // Only inside the scanned span (beyond it the parabola extrapolates).
      if (peak >= lo && peak <= hi) {
        reference = peak;
        from_profile = true;
      }
    }
  }
  int above = 0, below = 0;
  for (const LineExtent& e : pass) {
    if (&e == longest && !from_profile) continue;
    if (e.phi_rad > reference) {
      ++above;
    } else {
      ++below;
    }
  }
  for (LineExtent& e : pass) {
    if (&e == longest && !from_profile) {
      // The reference line itself: if the pass lies mostly above it, the
      // pass stopped near the centre (less than a frame): the centre is
      // below it.
      e.sign = above > below ? -1 : +1;
    } else {
      e.sign = e.phi_rad > reference ? -1 : +1;
    }
    finish(cfg, e);
  }
}

}  // namespace

std::vector<LineExtent> ScanLineExtent::line_extents(const Window& window, std::string* why) const {
  std::vector<LineExtent> out;
  line_extents_into(window, out, why);
  return out;
}

void ScanLineExtent::line_extents_into(const Window& window, std::vector<LineExtent>& out,
                                       std::string* why) const {
  out.clear();
  out.reserve(window.lines.size());
  ForegroundGate gate(config_.gate);
  if (gate.learn(window) == 0) {
    if (why) *why = "no returns closer than the background threshold";
    return;
  }
  const WindowSlope slopes = config_.window_slope ? window_slope(window) : WindowSlope{};
  const LineSolver solver(config_, azimuth_step(window), config_.window_slope ? &slopes : nullptr);
  Rejections rejected;
  LineScratch scratch;
  // Lines with returns in a row form a pass; a line without returns ends it.
  // The usable lines of a pass are consecutive in `out`: pass_start[k] is
  // where pass k begins.
  std::vector<size_t> pass_start;
  bool in_pass = false;
  // Foreground pulse indices of the current line; sized once to the longest
  // line (a resize per line zero-filled it).
  size_t longest = 0;
  for (const ScanLine& l : window.lines) longest = std::max(longest, l.pulses.size());
  std::vector<size_t> hit_buffer(longest);
  size_t* const hit = hit_buffer.data();
  LineExtent line;
  for (size_t j = 0; j < window.lines.size(); ++j) {
    // Branch-free: every pulse's index is written, the count advances only
    // for the foreground (the sphere's edges would mispredict twice a line).
    const std::vector<Pulse>& pulses = window.lines[j].pulses;
    const Pulse* const p = pulses.data();
    const size_t count = pulses.size();
    size_t n = 0;
    for (size_t i = 0; i < count; ++i) {
      hit[n] = i;
      n += gate.is_foreground(p[i]) ? 1 : 0;
    }
    if (n == 0) {
      in_pass = false;
      continue;
    }
    if (!in_pass) {
      pass_start.push_back(out.size());
      in_pass = true;
    }
    if (solver.solve(window.lines[j], j, std::span<const size_t>(hit, n), rejected, scratch,
                     line)) {
      out.push_back(line);
    }
  }
  if (out.empty()) {
    if (why) {
      *why = "no usable scan line (" + std::to_string(rejected.at_edge) +
             " cut by the frame or window edge, " + std::to_string(rejected.too_few) +
             " with fewer than " + std::to_string(config_.min_points_per_line) + " points)";
    }
    return;
  }
  pass_start.push_back(out.size());
  for (size_t k = 0; k + 1 < pass_start.size(); ++k) {
    const std::span<LineExtent> pass(out.data() + pass_start[k], pass_start[k + 1] - pass_start[k]);
    choose_signs(config_, pass);
  }
}

Estimate ScanLineExtent::locate(const Window& window) const {
  std::string why;
  // Kept from call to call on each thread: a locator calls this every half
  // second, and a fresh 100-150 kB vector each time came from new pages (page
  // faults: the slowest trials in the bench).
  thread_local std::vector<LineExtent> lines;
  thread_local std::vector<double> t, x, w;
  line_extents_into(window, lines, &why);
  int points = 0;
  for (const LineExtent& e : lines) points += e.points;
  if (static_cast<int>(lines.size()) < config_.min_lines) {
    if (lines.empty()) return Estimate::none(why, points, 0);
    return Estimate::none("only " + std::to_string(lines.size()) + " usable scan lines (need " +
                              std::to_string(config_.min_lines) + ")",
                          points, static_cast<int>(lines.size()));
  }
  t.resize(lines.size());
  double t_mean = 0.0;
  for (size_t j = 0; j < lines.size(); ++j) {
    t[j] = lines[j].t_s;
    t_mean += t[j];
  }
  t_mean /= static_cast<double>(lines.size());
  Estimate est;
  est.ok = true;
  est.t_s = t_mean;
  est.points = points;
  est.lines = static_cast<int>(lines.size());
  x.resize(lines.size());
  w.resize(lines.size());
  for (int axis = 0; axis < 3; ++axis) {
    for (size_t j = 0; j < lines.size(); ++j) {
      x[j] = lines[j].position_m(axis);
      w[j] = 1.0 / lines[j].variance_m2(axis);
    }
    const LineFit fit = regress(t, x, config_.weighted_regression ? &w : nullptr);  // eq. 38-40
    est.velocity_m_s(axis) = fit.slope;
    est.position_m(axis) = fit.x0 + fit.slope * t_mean;
  }
  return est;
}

}  // namespace ephor::sphere
