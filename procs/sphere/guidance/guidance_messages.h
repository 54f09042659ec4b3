#pragma once
// ephor-sphere-guidance's messages in and out, as its guide task converts
// them (out of main.cc, so that the fuzz target guidance_messages_fuzz.cc
// runs what the process runs): a SPHERE_ESTIMATE as SphereGuidance's input
// (SphereGuidance::on_estimate() checks it) and its answer as the
// SPHERE_GUIDANCE it publishes. Sensor frame of equations 35-37, metres, m/s,
// scan-clock seconds.

#include "common/sphere/guidance/sphere_guidance.h"
#include "ephor/sphere_estimate_t.hpp"
#include "ephor/sphere_guidance_t.hpp"

namespace ephor::sphere {

EstimateInput estimate_input_of(const sphere_estimate_t& m);

// The command and filtered state of `out` with the guidance's counts;
// range_to_capture_m from the config's capture distance. utime is the
// caller's to set.
sphere_guidance_t guidance_message_of(const GuidanceOutput& out, const SphereGuidance& guidance,
                                      const GuidanceConfig& config);

}  // namespace ephor::sphere
