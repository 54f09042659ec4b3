#include "common/stripe/stripe_scan.h"

#include <chrono>

namespace ephor::stripe {

std::vector<Eigen::Vector3d> ScanResult::cloud() const {
  std::vector<Eigen::Vector3d> out;
  out.reserve(point_count());
  for (const auto& s : stripes)
    for (const auto& p : s.points) out.push_back(p.table_mm);
  return out;
}

size_t ScanResult::point_count() const {
  size_t n = 0;
  for (const auto& s : stripes) n += s.points.size();
  return n;
}

ScanResult run_scan(const StripeWorld& world, const RangeFinder& finder,
                    const std::vector<Eigen::Isometry3d>& projector_poses, std::uint64_t seed,
                    arm::Joints start) {
  using Clock = std::chrono::steady_clock;
  ScanResult r;
  arm::Joints q = start;
  for (size_t i = 0; i < projector_poses.size(); ++i) {
    const Eigen::Isometry3d flange = flange_for_projector(projector_poses[i], finder.calibration());
    const auto next =
        world.cell().joints_for(flange, q, finder.arm_model().errors().zero_offset_rad);
    if (!next) {
      ++r.unreachable;
      continue;
    }
    q = *next;
    const auto t0 = Clock::now();
    const cv::Mat img = world.image(q, seed + i);
    const auto t1 = Clock::now();
    ScanStripe s{q, finder.measure(img, q)};
    const auto t2 = Clock::now();
    r.render_s += std::chrono::duration<double>(t1 - t0).count();
    r.process_s += std::chrono::duration<double>(t2 - t1).count();
    r.stripes.push_back(std::move(s));
  }
  return r;
}

}  // namespace ephor::stripe
