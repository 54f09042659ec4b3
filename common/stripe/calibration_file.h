#pragma once
// The light-stripe sensor's calibration file (stripe_calibration.proto,
// Protobuf text): what ephor-stripe-calibrate writes and the range process
// and scan planner read. The software's whole model of the robot and the
// cage: zero references and link errors (TrueArm), C_T, S_T and P
// (SensorCalibration), and the robot it was measured on.

#include <cstdint>
#include <string>
#include <vector>

#include "common/stripe/sensor_model.h"
#include "common/stripe/true_arm.h"

namespace ephor::stripe {

struct StripeCalibration {
  std::int64_t robot_seed = 0;
  ArmErrors arm;  // zero references and link errors of the software's model
  SensorCalibration sensor = SensorCalibration::drawing_cage();
  std::string measured;             // when and how
  std::vector<std::string> report;  // what each step found

  TrueArm arm_model() const { return TrueArm(arm); }
  // No file: the nominal arm and the cage from the mechanical drawings.
  static StripeCalibration drawing(std::int64_t robot_seed);
};

// Throws ephor::ConfigError naming the file, line and field: a missing file,
// a syntax error, an unknown field, a required field missing, a wrong count
// of values, a number not finite, a rotation that is not a unit quaternion,
// a camera that is not valid.
StripeCalibration load_stripe_calibration(const std::string& path);
// Throws ephor::ConfigError when `calibration` was measured on another robot
// ("PATH: measured on robot seed 3, this robot is seed 5").
void check_calibration_robot(const StripeCalibration& calibration, std::int64_t robot_seed,
                             const std::string& path);
// What a process's --calibration FILE and --robot-seed N give it: the file
// (looked up as resolve_repo_path does), checked against the robot, or the
// drawing (StripeCalibration::drawing) when `path` is empty. Throws
// ephor::ConfigError as the two above.
StripeCalibration calibration_from_flags(const std::string& path, std::int64_t robot_seed);
// The file's text (round-trips through load_stripe_calibration, to the last
// bit of every double).
std::string stripe_calibration_text(const StripeCalibration& calibration);
// Writes it; throws ephor::ConfigError when the file cannot be written.
void save_stripe_calibration(const std::string& path, const StripeCalibration& calibration);

}  // namespace ephor::stripe
