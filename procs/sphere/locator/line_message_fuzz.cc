// Fuzz target (issue 18): a stream of SPHERE_SCAN_LINE messages as
// ephor-sphere-locator takes them: each decoded as sphere_scan_line_t the
// way the bus does (a message that does not decode to its full size is
// dropped), line_message_of(), WindowAssembler::add() (which checks every
// line: counts that disagree with the arrays, non-finite or backward times,
// angles beyond +-pi, negative ranges, late lines, a ranger's restart), and
// every window it completes located by SphereLocator as the locate task does,
// its estimate put into a sphere_estimate_t and encoded. A refused line must
// say why; an estimate must be finite.
//
// Input: one byte choosing the algorithm (SLE or fit), the variant (paper or
// improved) and the locator's --window-s (0.05, 0.1 or 0.5 s), then up to
// 64 messages, each a 2-byte little-endian length and that many bytes.
// Seeds: fuzz_corpus/sphere_scan_line (a sphere 3 m away seen over three
// windows of 0.1 s, lines of 16 pulses).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/fuzz/fuzz_input.h"
#include "common/sphere/sphere_locator.h"
#include "ephor/sphere_estimate_t.hpp"
#include "ephor/sphere_scan_line_t.hpp"
#include "procs/sphere/locator/line_message.h"
#include "procs/sphere/locator/window_assembler.h"

namespace {

using namespace ephor;
using namespace ephor::sphere;

void locate(const SphereLocator& locator, const AssembledWindow& w) {
  double cpu_us = 0.0;
  const Estimate e = locator.locate(w.window, &cpu_us);
  if (!e.ok && e.reason.empty()) fuzz::fail("no estimate and no reason");
  if (e.ok && !(e.position_m.allFinite() && e.velocity_m_s.allFinite() && std::isfinite(e.t_s)))
    fuzz::fail("an estimate that is not finite");
  sphere_estimate_t m = estimate_message_of(e, w, locator.config());
  const int size = m.getEncodedSize();
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  if (m.encode(bytes.data(), 0, size) != size) fuzz::fail("the estimate does not encode");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const double kWindowS[] = {0.05, 0.1, 0.5};
  LocatorConfig config;
  config.algorithm = (data[0] & 1) != 0 ? Algorithm::kSphereFitting : Algorithm::kScanLineExtent;
  config.variant = (data[0] & 2) != 0 ? Variant::kPaper : Variant::kImproved;
  const SphereLocator locator(config);
  WindowAssembler assembler(kWindowS[(data[0] >> 2) % 3]);
  size_t at = 1;
  for (int k = 0; k < 64 && at + 2 <= size; ++k) {
    const size_t len = data[at] | (static_cast<size_t>(data[at + 1]) << 8);
    at += 2;
    if (len > size - at) break;
    sphere_scan_line_t m;
    const int n = static_cast<int>(len);
    const bool whole = m.decode(data + at, 0, n) == n;
    at += len;
    if (!whole) continue;  // the bus counts a decode error
    const std::string why = assembler.add(line_message_of(m));
    (void)why;  // "" when accepted; main.cc logs it
    for (const AssembledWindow& w : assembler.take_complete()) {
      if (w.lines_received <= 0 || w.lines_missing < 0) fuzz::fail("a window without lines");
      locate(locator, w);
    }
  }
  return 0;
}
