#pragma once
// The sphere system's LCM channels (paper 002; procs/sphere). Shared by its
// processes, its tests and the display; types in lcmtypes/sphere_*_t.lcm.

namespace ephor::sphere::channels {

// sphere_scan_line_t, ranger -> locator (and display): one per scan line.
inline constexpr const char* kScanLine = "SPHERE_SCAN_LINE";
// sphere_estimate_t, locator -> guidance: one per half-second window.
inline constexpr const char* kEstimate = "SPHERE_ESTIMATE";
// sphere_guidance_t, guidance -> ranger (the chaser): one per estimate.
inline constexpr const char* kGuidance = "SPHERE_GUIDANCE";
// sphere_truth_t, ranger -> tests, display only: 20 Hz and at each verdict.
inline constexpr const char* kTruth = "SPHERE_TRUTH";

}  // namespace ephor::sphere::channels
