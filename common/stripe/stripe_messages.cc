#include "common/stripe/stripe_messages.h"

#include <cmath>

namespace ephor::stripe {

cv::Mat image_of(const stripe_image_t& m, std::string* why) {
  auto bad = [&](const std::string& w) {
    if (why) *why = w;
    return cv::Mat();
  };
  if (m.width <= 0 || m.height <= 0 || m.width > 4096 || m.height > 4096)
    return bad("image size " + std::to_string(m.width) + " x " + std::to_string(m.height) +
               " px is not 1..4096");
  if (m.size != m.width * m.height || static_cast<int>(m.data.size()) != m.size)
    return bad("image of " + std::to_string(m.width) + " x " + std::to_string(m.height) +
               " px carries " + std::to_string(m.data.size()) + " bytes");
  for (double q : m.q)
    if (!std::isfinite(q)) return bad("joint readings are not finite");
  cv::Mat out(m.height, m.width, CV_8UC1);
  std::copy(m.data.begin(), m.data.end(), out.data);
  return out;
}

arm::Joints joints_of(const double q[6]) {
  arm::Joints out;
  for (int j = 0; j < 6; ++j) out[j] = q[j];
  return out;
}

void set_joints(const arm::Joints& q, double out[6]) {
  for (int j = 0; j < 6; ++j) out[j] = q[j];
}

Stripe stripe_of(const stripe_profile_t& m, std::string* why) {
  Stripe s;
  auto bad = [&](const std::string& w) {
    if (why) *why = w;
    return Stripe{};
  };
  const auto n = static_cast<size_t>(std::max(0, m.num_rows));
  if (m.num_rows < 0 || m.num_rows > 4096 || m.row.size() != n || m.u_px.size() != n ||
      m.width_px.size() != n || m.peak.size() != n)
    return bad("its arrays disagree with num_rows " + std::to_string(m.num_rows));
  for (double q : m.q)
    if (!std::isfinite(q)) return bad("joint readings are not finite");
  s.points.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(m.u_px[i]) || !std::isfinite(m.width_px[i]) || !std::isfinite(m.peak[i]))
      return bad("row " + std::to_string(m.row[i]) + " is not finite");
    if (i > 0 && m.row[i] <= m.row[i - 1]) return bad("rows do not increase");
    StripePoint p;
    p.row = m.row[i];
    p.u_px = m.u_px[i];
    p.width_px = m.width_px[i];
    p.peak = m.peak[i];
    s.points.push_back(p);
  }
  s.runs_found = m.runs_found;
  s.runs_dropped = m.runs_dropped;
  return s;
}

stripe_profile_t profile_of(const stripe_image_t& image, const Stripe& stripe,
                            const StripeExtractorOptions& options) {
  stripe_profile_t m{};
  m.utime = image.utime;
  m.image_index = image.image_index;
  m.request_id = image.request_id;
  m.scan_id = image.scan_id;
  m.stripe_index = image.stripe_index;
  for (int j = 0; j < 6; ++j) m.q[j] = image.q[j];
  m.method = centre_method_name(options.method);
  m.threshold = options.threshold;
  m.num_rows = static_cast<int32_t>(stripe.points.size());
  m.row.clear();
  m.u_px.clear();
  m.width_px.clear();
  m.peak.clear();
  for (const StripePoint& p : stripe.points) {
    m.row.push_back(p.row);
    m.u_px.push_back(p.u_px);
    m.width_px.push_back(static_cast<float>(p.width_px));
    m.peak.push_back(static_cast<float>(p.peak));
  }
  m.runs_found = stripe.runs_found;
  m.runs_dropped = stripe.runs_dropped;
  return m;
}

std::vector<Eigen::Vector3d> points_of(const stripe_points_t& m, std::string* why) {
  const auto n = static_cast<size_t>(std::max(0, m.num_points));
  if (m.num_points < 0 || m.x_mm.size() != n || m.y_mm.size() != n || m.z_mm.size() != n) {
    if (why) *why = "its arrays disagree with num_points " + std::to_string(m.num_points);
    return {};
  }
  std::vector<Eigen::Vector3d> out;
  out.reserve(n);
  for (size_t i = 0; i < n; ++i) out.emplace_back(m.x_mm[i], m.y_mm[i], m.z_mm[i]);
  return out;
}

void set_points(const std::vector<RangePoint>& points, stripe_points_t& m) {
  m.num_points = static_cast<int32_t>(points.size());
  m.x_mm.clear();
  m.y_mm.clear();
  m.z_mm.clear();
  for (const RangePoint& p : points) {
    m.x_mm.push_back(static_cast<float>(p.table_mm.x()));
    m.y_mm.push_back(static_cast<float>(p.table_mm.y()));
    m.z_mm.push_back(static_cast<float>(p.table_mm.z()));
  }
}

}  // namespace ephor::stripe
