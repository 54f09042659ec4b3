#pragma once
// The light-stripe system's LCM channels (paper 004; procs/stripe). Shared by
// its processes, its tests and the display; types in lcmtypes/stripe_*_t.lcm.
// The arm's channels (ARM_GOAL, MOTION_DONE, ARM_STATE, ARM_TRAJECTORY,
// ARM_SERVO) are the shared ones of common/lcm/channels.h.

namespace ephor::stripe::channels {

// stripe_capture_t, planner / calibrate -> sim: take one image.
inline constexpr const char* kCapture = "STRIPE_CAPTURE";
// stripe_image_t, sim -> stripe, planner, calibrate, display: the image and
// the joint readings it was taken at.
inline constexpr const char* kImage = "STRIPE_IMAGE";
// stripe_profile_t, stripe -> range, display: the stripe's centre line per row.
inline constexpr const char* kProfile = "STRIPE_PROFILE";
// stripe_points_t, range -> display, tests: one stripe's 3-D points.
inline constexpr const char* kPoints = "STRIPE_POINTS";
// stripe_scan_t, planner -> range, display, tests: the scan's state.
inline constexpr const char* kScan = "STRIPE_SCAN";
// stripe_cloud_t, range -> planner, display, tests: a scan's cloud is complete.
inline constexpr const char* kCloud = "STRIPE_CLOUD";
// camera_frame_t, sim -> display: each image again as a plain camera frame
// (the shared page's /api/frame.jpg, lcm-spy).
inline constexpr const char* kCamera = "STRIPE_CAMERA";
// stripe_truth_t, sim -> tests, display only: the world as it was.
inline constexpr const char* kTruth = "STRIPE_TRUTH";

}  // namespace ephor::stripe::channels
