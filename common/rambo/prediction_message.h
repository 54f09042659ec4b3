#pragma once
// rambo_prediction_t (RAMBO_PREDICTION) to and from the planner's
// FittedMotion: the predictor's rigid-body state and, for the paper's
// polynomial fits (a carried target), the polynomial itself, so that the
// planner and the simulator's scoring evaluate the same motion the
// predictor fitted. The only LCM in common/rambo, apart from the pure core
// (as common/arm's servo_messages).
#include <optional>
#include <string>

#include "common/rambo/tagging_planner.h"
#include "ephor/rambo_prediction_t.hpp"

namespace ephor::rambo {

// The motion the message carries, on a clock where ref_utime is t_ref_s (s).
// nullopt with `why` for a message that is not fitted, not finite, or
// carries a polynomial that is not one (degree, scale, rotation).
std::optional<FittedMotion> motion_from_message(const rambo_prediction_t& m, double t_ref_s,
                                                std::string* why);

// Writes `p` (fitted on a clock where ref_utime is t_ref_s) into `out`'s
// poly_ fields and sets its model to "polynomial"; no_polynomial() marks a
// rigid-body message (poly_terms 0, as a zero-initialised message).
void polynomial_to_message(const PolynomialMotion& p, double t_ref_s, rambo_prediction_t* out);
void no_polynomial(rambo_prediction_t* out);

}  // namespace ephor::rambo
