#include "common/sphere/scan_file.h"

#include <sstream>

#include <gtest/gtest.h>

namespace ephor::sphere {
namespace {

std::string error_of(const std::string& text) {
  std::istringstream in(text);
  try {
    ScanFile::read(in, "scan.csv");
  } catch (const ScanFileError& e) {
    return e.what();
  }
  return "";
}

const std::string kHead = "t_s,line,azimuth_rad,elevation_rad,range_m\n";

TEST(ScanFileTest, RoundTripsPulsesAndMisses) {
  std::vector<ScanLine> lines = {
      {0, {{0.0, -0.01, 0.02, 4.93}, {0.0001, -0.009, 0.02, std::nan("")}}},
      {1, {{0.0002, 0.01, 0.0199, 61.5}}}};
  std::stringstream ss;
  ScanFile::write(ss, lines);
  const std::vector<ScanLine> back = ScanFile::read(ss, "x");
  ASSERT_EQ(back.size(), 2u);
  ASSERT_EQ(back[0].pulses.size(), 2u);
  EXPECT_EQ(back[1].id, 1);
  EXPECT_NEAR(back[0].pulses[0].range_m, 4.93, 1e-9);
  EXPECT_FALSE(back[0].pulses[1].has_range());
  EXPECT_NEAR(back[1].pulses[0].t_s, 0.0002, 1e-12);
  EXPECT_NEAR(back[1].pulses[0].elevation_rad, 0.0199, 1e-12);
}

TEST(ScanFileTest, RefusesAWrongHeader) {
  EXPECT_EQ(error_of(""), "scan.csv:1: empty file (expected the header)");
  EXPECT_NE(error_of("t,line,az,el,r\n").find("scan.csv:1: header must be"), std::string::npos);
}

TEST(ScanFileTest, RefusesALetterInANumberWithItsLineNumber) {
  EXPECT_EQ(error_of(kHead + "0.0,0,0.01,0.0,5.0\n0.0001,0,0.0x1,0.0,5.0\n"),
            "scan.csv:3: azimuth_rad '0.0x1' is not a finite number");
  EXPECT_EQ(error_of(kHead + "0.0,0,0.01,0.0,abc\n"),
            "scan.csv:2: range_m 'abc' is not a finite number");
  EXPECT_EQ(error_of(kHead + "nan,0,0.01,0.0,5\n"), "scan.csv:2: t_s 'nan' is not a finite number");
}

TEST(ScanFileTest, RefusesAWrongColumnCount) {
  EXPECT_EQ(error_of(kHead + "0.0,0,0.01,0.0\n"), "scan.csv:2: expected 5 columns, found 4");
  EXPECT_EQ(error_of(kHead + "0.0,0,0.01,0.0,5,\n"), "scan.csv:2: expected 5 columns, found 6");
}

TEST(ScanFileTest, RefusesATimeBeyondTheLimitAndTooManyWindows) {
  // Found by the fuzz target sphere_scan: t_s = 1.7e46 s made split_windows
  // cast out of range; 1e9 s would have made two billion empty windows.
  EXPECT_NE(error_of(kHead + "1e9,0,0.01,0.0,5\n").find("scan.csv:2: t_s '1e9' is beyond"),
            std::string::npos);
  std::istringstream in(kHead + "0,0,0.01,0.0,5\n99999,0,0.01,0.0,5\n");
  const auto lines = ScanFile::read(in, "scan.csv");
  EXPECT_EQ(split_windows(lines, 0.5).size(), 199999u);
  EXPECT_THROW(split_windows(lines, 0.01), std::invalid_argument);
}

TEST(ScanFileTest, RefusesTimeGoingBackwards) {
  EXPECT_NE(error_of(kHead + "0.5,0,0.01,0.0,5\n0.4,0,0.01,0.0,5\n")
                .find("scan.csv:3: time goes backwards"),
            std::string::npos);
}

TEST(ScanFileTest, RefusesNonIntegerLineNegativeRangeAndWildAngles) {
  EXPECT_EQ(error_of(kHead + "0,1.5,0.01,0.0,5\n"), "scan.csv:2: line '1.5' is not an integer");
  EXPECT_EQ(error_of(kHead + "0,1,0.01,0.0,-5\n"), "scan.csv:2: negative range_m");
  EXPECT_NE(error_of(kHead + "0,1,4.0,0.0,5\n").find("angle out of range"), std::string::npos);
}

TEST(ScanFileTest, WindowsTileTimeFromZeroAndKeepEmptyOnes) {
  std::vector<ScanLine> lines = {{0, {{0.1, 0, 0, 5}, {0.6, 0, 0, 5}}}, {1, {{1.7, 0, 0, 5}}}};
  const std::vector<Window> w = split_windows(lines, 0.5);
  ASSERT_EQ(w.size(), 4u);
  EXPECT_EQ(w[0].lines.size(), 1u);
  EXPECT_EQ(w[1].lines.size(), 1u);  // the straddling line split by time
  EXPECT_TRUE(w[2].lines.empty());
  EXPECT_DOUBLE_EQ(w[3].t_begin_s, 1.5);
}

}  // namespace
}  // namespace ephor::sphere
