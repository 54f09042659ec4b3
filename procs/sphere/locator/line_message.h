#pragma once
// The locator's messages in and out: a SPHERE_SCAN_LINE message as the
// locator takes it (its fields as a LineMessage for WindowAssembler::add(),
// which checks them) and a window's estimate as SPHERE_ESTIMATE. Moved out of
// main.cc so the fuzz target line_message_fuzz.cc runs what the process runs.

#include "common/sphere/sphere_locator.h"
#include "ephor/sphere_estimate_t.hpp"
#include "ephor/sphere_scan_line_t.hpp"
#include "procs/sphere/locator/window_assembler.h"

namespace ephor::sphere {

LineMessage line_message_of(const sphere_scan_line_t& m);

// A located window as published: position, velocity and time NaN when the
// window gave no estimate (e.reason says why). utime and cpu_us are the
// caller's to set.
sphere_estimate_t estimate_message_of(const Estimate& e, const AssembledWindow& w,
                                      const LocatorConfig& config);

}  // namespace ephor::sphere
