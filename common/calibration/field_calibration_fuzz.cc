// Fuzz target (issue 18): the image-to-field calibration file as ephor-arm and
// the shepherding planner read it (FieldCalibration::load), then used as they
// use it: both directions in both planes and at a height. A calibration the
// loader accepts must also round-trip through to_text(). Bad input must end
// in ConfigError. Seeds: fuzz_corpus/field_calibration.
#include <cstddef>
#include <cstdint>

#include "common/calibration/field_calibration.h"
#include "common/config/text_proto.h"
#include "common/fuzz/fuzz_input.h"

using ephor::calibration::FieldCalibration;
using ephor::calibration::Plane;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static ephor::fuzz::FuzzInputFile file;
  try {
    const FieldCalibration c = FieldCalibration::load(file.write(data, size));
    for (const Plane plane : {Plane::kObject, Plane::kElevation}) {
      const Eigen::Vector2d f = c.image_to_field(256.0, 241.0, plane);
      (void)c.field_to_image(f.x(), f.y(), plane);
      (void)c.image_vector_to_field(Eigen::Vector2d(1.0, 0.0), plane);
    }
    (void)c.image_to_field_at_height(100.0, 100.0, 20.0);
    const std::string text = c.to_text("fuzz");
    try {
      (void)FieldCalibration::parse(text, "round-trip");
    } catch (const ephor::ConfigError& e) {
      ephor::fuzz::fail(std::string("an accepted calibration does not round-trip: ") + e.what());
    }
  } catch (const ephor::ConfigError&) {
  }
  return 0;
}
