#pragma once
// ephor-catch-worldmodel's messages in and out, as its model task converts
// them (out of main.cc, so that the fuzz target world_message_fuzz.cc runs
// what the process runs): a CATCH_BALL's centroid, and a model frame as the
// CATCH_WORLD it publishes.

#include <optional>

#include <Eigen/Core>

#include "common/catch/worldmodel/ball_world_model.h"
#include "ephor/catch_ball_t.hpp"
#include "ephor/catch_world_t.hpp"

namespace ephor::catching {

// The ball's image centroid (px) when the vision found one; nullopt when it
// did not, or when u or v is not finite (*bad set: counted, not used).
std::optional<Eigen::Vector2d> centroid_of(const catch_ball_t& ball, bool* bad);

// The frame as published: state, measurement and prediction NaN where the
// frame has none; with the exit's spread (--spread-samples), the spread's
// cover as the exit and catch point. latency_ms is the caller's to set.
catch_world_t world_message_of(const BallFrame& f, const catch_ball_t& ball);

}  // namespace ephor::catching
