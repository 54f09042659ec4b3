#pragma once
// The light-stripe system's messages (lcmtypes/stripe_*_t.lcm) to and from
// common/stripe's types, for its processes, tests and display.

#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "common/arm/puma560.h"
#include "common/geometry/message_pose.h"
#include "common/stripe/range_finder.h"
#include "common/stripe/stripe_extractor.h"
#include "ephor/stripe_image_t.hpp"
#include "ephor/stripe_points_t.hpp"
#include "ephor/stripe_profile_t.hpp"

namespace ephor::stripe {

// The image's pixels (a copy), or why it is not a valid 8-bit image (sizes
// that disagree with its data, non-positive or above 4096).
cv::Mat image_of(const stripe_image_t& m, std::string* why);
// Joint readings of a message's q[6] (rad); why non-finite.
arm::Joints joints_of(const double q[6]);
void set_joints(const arm::Joints& q, double out[6]);

// A profile's rows as the extractor's Stripe (row, u_px, width_px, peak);
// why not when its arrays disagree with num_rows, rows do not increase or a
// number is not finite.
Stripe stripe_of(const stripe_profile_t& m, std::string* why);
// The profile the stripe process publishes for image `m`: its stripe's rows,
// the image's time, indices and joints, the extractor's method and
// threshold. cpu_us is the caller's to set.
stripe_profile_t profile_of(const stripe_image_t& m, const Stripe& stripe,
                            const StripeExtractorOptions& options);

// The points of a stripe_points_t (mm, table frame); why not when its
// arrays disagree with num_points.
std::vector<Eigen::Vector3d> points_of(const stripe_points_t& m, std::string* why);
void set_points(const std::vector<RangePoint>& points, stripe_points_t& m);

// Row-major 3x3 and translation of a pose, as the truth message carries them.
using geometry::pose_of;
using geometry::set_pose;

}  // namespace ephor::stripe
