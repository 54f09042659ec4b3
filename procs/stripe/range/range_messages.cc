#include "procs/stripe/range/range_messages.h"

#include <ctime>
#include <utility>

#include "common/stripe/stripe_messages.h"

namespace ephor::stripe {

namespace {

double thread_cpu_us() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) * 1e-3;
}

}  // namespace

std::optional<RangedStripe> range_profile(const stripe_profile_t& m, const RangeFinder& finder,
                                          std::string* why) {
  std::string refused;
  const Stripe stripe = stripe_of(m, &refused);
  if (!refused.empty()) {
    if (why) *why = refused;
    return std::nullopt;
  }
  const double c0 = thread_cpu_us();
  const std::vector<RangePoint> pts = finder.to_table(stripe, joints_of(m.q));
  const double cpu = thread_cpu_us() - c0;
  RangedStripe r;
  r.points.reserve(pts.size());
  for (const RangePoint& p : pts) r.points.push_back(p.table_mm);
  stripe_points_t& out = r.message;
  out.utime = m.utime;
  out.image_index = m.image_index;
  out.scan_id = m.scan_id;
  out.stripe_index = m.stripe_index;
  out.cpu_us = static_cast<float>(cpu);
  set_points(pts, out);
  return r;
}

bool add_to_cloud(RangedStripe& r, CloudAccumulator& clouds) {
  stripe_points_t& out = r.message;
  const bool added =
      out.scan_id > 0 && clouds.add(out.scan_id, out.stripe_index, std::move(r.points));
  out.scan_stripes = clouds.stripes(out.scan_id);
  out.scan_points = clouds.points(out.scan_id);
  return added;
}

stripe_cloud_t* on_scan(const stripe_scan_t& m, CloudAccumulator& clouds, FinishedClouds& finished,
                        double now_s) {
  if (m.state != stripe_scan_t::STATE_CAPTURED) return nullptr;
  const auto it = finished.find(m.scan_id);
  if (it != finished.end()) return &it->second;
  clouds.captured(m.scan_id, m.stripes_captured, now_s);
  return nullptr;
}

stripe_cloud_t cloud_message_of(const CompletedCloud& c) {
  stripe_cloud_t m{};
  m.scan_id = c.scan_id;
  m.stripes = c.stripes;
  m.stripes_missing = c.stripes_missing;
  m.points = static_cast<int64_t>(c.points.size());
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  if (!c.points.empty()) {
    lo = hi = c.points.front();
    for (const auto& p : c.points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  for (int i = 0; i < 3; ++i) {
    m.bbox_mm[i] = lo[i];
    m.bbox_mm[3 + i] = hi[i];
  }
  return m;
}

void remember_cloud(FinishedClouds& finished, const stripe_cloud_t& m) {
  finished[m.scan_id] = m;
  while (finished.size() > kFinishedCloudsKept) finished.erase(finished.begin());
}

}  // namespace ephor::stripe
