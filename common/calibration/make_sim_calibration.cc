// ephor-make-sim-calibration: writes the calibration of the simulator's
// default overhead camera (FieldCalibration::from_camera with the default
// OverheadCamera and Workcell), e.g. deploy/calibration/sim.pbtxt.
//
//   ephor-make-sim-calibration --out deploy/calibration/sim.pbtxt

#include <cstdio>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "common/calibration/field_calibration.h"
#include "common/runtime/process_args.h"

int main(int argc, char** argv) {
  CLI::App app{"ephor-make-sim-calibration: calibration of the simulator's default camera"};
  std::string out;
  app.add_option("--out", out, "calibration file to write (Protobuf text)")->required();
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  try {
    const auto cal = ephor::calibration::FieldCalibration::from_camera(
        ephor::geometry::OverheadCamera{}, ephor::geometry::Workcell{});
    cal.save(
        out,
        "Calibration of the simulator's default overhead camera "
        "(common/geometry/overhead_camera.h)\n"
        "and work cell (common/geometry/workcell.h). Generated, do not edit by hand:\n"
        "  build/bin/ephor-make-sim-calibration --out deploy/calibration/sim.pbtxt\n"
        "(FieldCalibration::from_camera: least-squares affine fit per plane to the true pinhole\n"
        "projection of the four field corners.) Schema: common/calibration/calibration.proto.");
    std::printf("wrote %s\n", out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ephor-make-sim-calibration: %s\n", e.what());
    return 1;
  }
  return 0;
}
