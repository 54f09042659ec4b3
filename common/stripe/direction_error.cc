#include "common/stripe/direction_error.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/stripe/pyramid_apex.h"
#include "common/stripe/stripe_scan.h"

namespace ephor::stripe {

std::vector<ApexView> section5_views() {
  constexpr double kDeg = std::numbers::pi / 180.0;
  std::vector<std::pair<Eigen::Vector3d, std::string>> approaches = {{{0, 0, 1}, "down"}};
  const double tilt = 25.0 * kDeg;
  for (int k = 0; k < 4; ++k) {
    const double az = k * 90.0 * kDeg;
    approaches.push_back({Eigen::Vector3d(std::sin(tilt) * std::cos(az),
                                          std::sin(tilt) * std::sin(az), std::cos(tilt)),
                          "tilt25az" + std::to_string(k * 90)});
  }
  std::vector<ApexView> out;
  for (const auto& [approach, name] : approaches)
    for (int s = 0; s < 2; ++s)
      for (double d : {270.0, 330.0}) {
        ApexView v;
        v.approach = approach;
        v.stripe_hint = s == 0 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
        v.distance_mm = d;
        v.label = name + (s == 0 ? "/stripe-x/" : "/stripe-y/") + std::to_string(int(d));
        out.push_back(v);
      }
  return out;
}

DirectionError measure_direction_error(const StripeWorld& world, const RangeFinder& finder,
                                       const std::vector<ApexView>& views,
                                       const Eigen::Vector3d& true_apex_mm, std::uint64_t seed) {
  DirectionError r;
  for (size_t i = 0; i < views.size(); ++i) {
    const ApexView& v = views[i];
    const auto poses =
        sweep_projector_poses(true_apex_mm, v.approach, v.distance_mm, v.stripe_hint, 50.0, 10.0);
    const ScanResult scan = run_scan(world, finder, poses, seed + 100 * i);
    r.unreachable_poses += scan.unreachable;
    // Start the face split at the cloud's top (the mean of its highest 1 %):
    // an uncalibrated robot can shift the pyramid by centimetres.
    auto cloud = scan.cloud();
    Eigen::Vector3d start = true_apex_mm;
    if (!cloud.empty()) {
      auto top = cloud;
      const size_t k = std::max<size_t>(1, top.size() / 100);
      std::partial_sort(top.begin(), top.begin() + k, top.end(),
                        [](const auto& a, const auto& b) { return a.z() > b.z(); });
      start = Eigen::Vector3d::Zero();
      for (size_t j = 0; j < k; ++j) start += top[j];
      start /= static_cast<double>(k);
    }
    const auto apex = PyramidApex::locate(cloud, start);
    r.apex_mm.push_back(apex ? std::optional<Eigen::Vector3d>(apex->apex_mm) : std::nullopt);
    if (apex) {
      r.mean_mm += apex->apex_mm;
      ++r.located;
    }
  }
  if (r.located > 0) r.mean_mm /= r.located;
  for (const auto& a : r.apex_mm) {
    if (!a) continue;
    r.worst_from_mean_mm = std::max(r.worst_from_mean_mm, (*a - r.mean_mm).norm());
    r.worst_from_truth_mm = std::max(r.worst_from_truth_mm, (*a - true_apex_mm).norm());
  }
  return r;
}

}  // namespace ephor::stripe
