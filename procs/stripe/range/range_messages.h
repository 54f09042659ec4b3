#pragma once
// ephor-stripe-range's handling of its messages, as its tasks do it (out of
// main.cc, so that the fuzz target range_messages_fuzz.cc runs what the
// process runs): a STRIPE_PROFILE checked (stripe_of) and ranged into the
// STRIPE_POINTS it publishes and the scan's cloud (CloudAccumulator); a
// STRIPE_SCAN's CAPTURED; a completed cloud as the STRIPE_CLOUD it publishes.
// Points in mm, table frame; times in s of the process's monotonic clock.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/stripe/range_finder.h"
#include "ephor/stripe_cloud_t.hpp"
#include "ephor/stripe_points_t.hpp"
#include "ephor/stripe_profile_t.hpp"
#include "ephor/stripe_scan_t.hpp"
#include "procs/stripe/range/cloud_accumulator.h"

namespace ephor::stripe {

struct RangedStripe {
  // The profile's indices, its points and the thread CPU time of the
  // conversion; scan_stripes and scan_points are add_to_cloud()'s to set.
  stripe_points_t message;
  std::vector<Eigen::Vector3d> points;  // the same points in double, for the cloud
};

// The profile's stripe to 3-D points through the collineation of its joint
// readings, or nullopt and *why when stripe_of() refuses the profile.
std::optional<RangedStripe> range_profile(const stripe_profile_t& m, const RangeFinder& finder,
                                          std::string* why);

// The stripe's points into its scan's cloud (a profile of scan 0 belongs to
// none), then the scan's counts so far into r.message. False when it was not
// added: no scan, a repeat or the scan already complete.
bool add_to_cloud(RangedStripe& r, CloudAccumulator& clouds);

// The finished scans' STRIPE_CLOUD messages, the newest kept by scan id.
using FinishedClouds = std::map<int64_t, stripe_cloud_t>;
constexpr size_t kFinishedCloudsKept = 8;

// A STRIPE_SCAN: only STATE_CAPTURED counts. For a scan finished already the
// message to say again (the planner has not heard it), else nullptr and the
// planner's count of captured stripes given to `clouds`.
stripe_cloud_t* on_scan(const stripe_scan_t& m, CloudAccumulator& clouds, FinishedClouds& finished,
                        double now_s);

// A complete cloud's STRIPE_CLOUD: counts and bounding box (zero when it has
// no points). utime, path and error are the caller's to set.
stripe_cloud_t cloud_message_of(const CompletedCloud& c);
// Keeps `m` to be said again, dropping the oldest beyond kFinishedCloudsKept.
void remember_cloud(FinishedClouds& finished, const stripe_cloud_t& m);

}  // namespace ephor::stripe
