#pragma once
// A SPHERE_SCAN_LINE message as the locator takes it: its fields as a
// LineMessage for WindowAssembler::add(), which checks them (moved out of
// main.cc so the fuzz target line_message_fuzz.cc runs what the process runs).

#include "ephor/sphere_scan_line_t.hpp"
#include "procs/sphere/locator/window_assembler.h"

namespace ephor::sphere {

LineMessage line_message_of(const sphere_scan_line_t& m);

}  // namespace ephor::sphere
