#pragma once
// The RAMBO system's LCM channels (paper 001; procs/rambo). Shared by its
// processes and tests; types in lcmtypes/rambo_*_t.lcm. Header only, no LCM.

namespace ephor::rambo::channels {

// rambo_features_t, the features process (from CAMERA) -> pose.
inline constexpr const char* kFeatures = "RAMBO_FEATURES";
// rambo_features_t, sim -> pose: the oracle (projected vertices + noise).
inline constexpr const char* kFeaturesOracle = "RAMBO_FEATURES_ORACLE";
// rambo_pose_t, pose -> predictor: one per frame with triples.
inline constexpr const char* kPose = "RAMBO_POSE";
// The solvePnPRansac peer on some frames (rambo_pose_t; ephor-rambo-pose --peer-every).
inline constexpr const char* kPosePeer = "RAMBO_POSE_PEER";
// rambo_prediction_t, predictor -> planner: after every pose.
inline constexpr const char* kPrediction = "RAMBO_PREDICTION";
// rambo_plan_t, planner -> display, tests.
inline constexpr const char* kPlan = "RAMBO_PLAN";
// rambo_indicator_t, sim (the target's electronics) -> planner, tests.
inline constexpr const char* kIndicator = "RAMBO_INDICATOR";
// rambo_truth_t, sim -> tests, display only.
inline constexpr const char* kTruth = "RAMBO_TRUTH";

}  // namespace ephor::rambo::channels
