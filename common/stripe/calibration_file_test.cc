// The calibration file: a round trip to the last bit, and each kind of bad
// file refused with the field named.

#include "common/stripe/calibration_file.h"

#include <fstream>

#include <gtest/gtest.h>

#include "common/config/text_proto.h"
#include "common/stripe/scan_geometry.h"
#include "common/stripe/stripe_world.h"

namespace ephor::stripe {
namespace {

std::string temp_file(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

StripeCalibration measured() {
  const RobotTruth t = RobotTruth::draw(4);
  StripeCalibration c;
  c.robot_seed = 4;
  c.arm = t.arm.errors();
  c.sensor = t.cage;
  c.sensor.camera.fx_px = 626.25;
  c.measured = "test";
  c.report = {"zero references: ...", "projector plane: ..."};
  return c;
}

TEST(CalibrationFile, RoundTripsEveryNumberExactly) {
  const StripeCalibration c = measured();
  const std::string path = temp_file("round.pbtxt", stripe_calibration_text(c));
  const StripeCalibration back = load_stripe_calibration(path);
  EXPECT_EQ(back.robot_seed, 4);
  for (int j = 0; j < 6; ++j) {
    EXPECT_NEAR(back.arm.zero_offset_rad[j], c.arm.zero_offset_rad[j], 1e-15);
    EXPECT_NEAR(back.arm.dh_error[j].d_mm, c.arm.dh_error[j].d_mm, 1e-15);
    EXPECT_NEAR(back.arm.dh_error[j].alpha_rad, c.arm.dh_error[j].alpha_rad, 1e-15);
  }
  EXPECT_TRUE(back.sensor.camera_in_flange.isApprox(c.sensor.camera_in_flange, 1e-14));
  EXPECT_TRUE(back.sensor.projector_in_flange.isApprox(c.sensor.projector_in_flange, 1e-14));
  EXPECT_EQ(back.sensor.camera.fx_px, 626.25);
  EXPECT_EQ(back.report, c.report);
  // Written again, the same text.
  EXPECT_EQ(stripe_calibration_text(back), stripe_calibration_text(c));
}

TEST(CalibrationFile, NominalLinksAreLeftOut) {
  StripeCalibration c = StripeCalibration::drawing(2);
  const std::string text = stripe_calibration_text(c);
  EXPECT_EQ(text.find("link_error"), std::string::npos);
  const StripeCalibration back = load_stripe_calibration(temp_file("drawing.pbtxt", text));
  EXPECT_TRUE(back.sensor.camera_in_flange.isApprox(c.sensor.camera_in_flange, 1e-14));
}

void expect_refused(const std::string& text, const std::string& what) {
  const std::string path = temp_file("bad.pbtxt", text);
  try {
    load_stripe_calibration(path);
    FAIL() << "accepted a file without " << what;
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

std::string without(const std::string& text, const std::string& start, const std::string& end) {
  const size_t a = text.find(start);
  const size_t b = text.find(end, a);
  return text.substr(0, a) + text.substr(b + end.size());
}

TEST(CalibrationFile, MissingOrBadFieldsAreNamed) {
  const std::string good = stripe_calibration_text(measured());
  expect_refused(without(good, "robot_seed", "\n"), "robot_seed");
  expect_refused(without(good, "camera_in_flange {", "}\n"), "camera_in_flange");
  expect_refused(without(good, "projector_in_flange {", "}\n"), "projector_in_flange");
  expect_refused(without(good, "camera {", "}\n"), "camera");
  expect_refused(without(good, "  fy_px", "\n"), "camera.fy_px");
  std::string five = good;
  five.erase(five.find("zero_offset_deg"),
             five.find('\n', five.find("zero_offset_deg")) - five.find("zero_offset_deg") + 1);
  expect_refused(five, "zero_offset_deg");
  expect_refused(good + "unknown_field: 3\n", "unknown_field");
  expect_refused(good + "robot_seed: \"x\"\n", "robot_seed");
  const size_t q = good.find("quaternion_wxyz: ");
  std::string bad_q = good;
  bad_q.replace(q, good.find('\n', q) - q, "quaternion_wxyz: 2");
  expect_refused(bad_q, "quaternion");
  expect_refused("", "robot_seed");
}

TEST(CalibrationFile, AnotherRobotIsRefused) {
  const StripeCalibration c = measured();
  EXPECT_NO_THROW(check_calibration_robot(c, 4, "f.pbtxt"));
  try {
    check_calibration_robot(c, 5, "f.pbtxt");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(
        std::string(e.what()).rfind("f.pbtxt: measured on robot seed 4, this robot is seed 5", 0),
        0u)
        << e.what();
  }
}

TEST(CalibrationFile, WorkcellFileGivesTheDefaultCell) {
  geometry::Workcell w;
  w.field_length_mm = 1100;
  w.field_width_mm = 1000;
  w.base_x_mm = 0;
  w.base_y_mm = 500;
  w.base_z_mm = 450;
  w.base_yaw_rad = 0;
  const StripeWorkcell cell = StripeWorkcell::from_workcell(w);
  EXPECT_TRUE(cell.base_in_table.isApprox(StripeWorkcell{}.base_in_table, 1e-12));
}

}  // namespace
}  // namespace ephor::stripe
