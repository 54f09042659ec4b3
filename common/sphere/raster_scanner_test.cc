#include "common/sphere/raster_scanner.h"

#include <cmath>

#include <gtest/gtest.h>

namespace ephor::sphere {
namespace {

constexpr double kDeg = M_PI / 180.0;

TEST(RasterScannerTest, StartsUpperLeftScansRightAndDownThenTurnsAround) {
  RasterScannerConfig c;
  c.half_extent_deg = 1.0;  // line 2 ms, frame 0.2 s
  const RasterScanner s(c);
  EXPECT_NEAR(s.line_duration_s(), 0.002, 1e-12);
  EXPECT_NEAR(s.frame_duration_s(), 0.2, 1e-12);
  const ScanDirection d0 = s.direction_at(0.0);
  EXPECT_NEAR(d0.azimuth_rad, -1.0 * kDeg, 1e-12);
  EXPECT_NEAR(d0.elevation_rad, 1.0 * kDeg, 1e-12);
  const ScanDirection d1 = s.direction_at(0.001);  // half a line: centre, 0.01 deg lower
  EXPECT_NEAR(d1.azimuth_rad, 0.0, 1e-12);
  EXPECT_NEAR(d1.elevation_rad, 0.99 * kDeg, 1e-12);
  EXPECT_EQ(d1.line, 0);
  const ScanDirection d2 = s.direction_at(0.0025);  // second line runs back right to left
  EXPECT_EQ(d2.line, 1);
  EXPECT_NEAR(d2.azimuth_rad, 0.5 * kDeg, 1e-12);
  const ScanDirection d3 = s.direction_at(0.25);  // second frame runs back up
  EXPECT_NEAR(d3.elevation_rad, -0.5 * kDeg, 1e-12);
  EXPECT_NEAR(s.azimuth_step_rad(), 0.1 * kDeg, 1e-15);  // 10 kHz: 0.1 deg between pulses
}

// Table 2 of the paper: half angular extent (deg) and frames per 0.5 s trial.
struct Table2Row {
  double distance_m, half_extent_deg, frames;
};
constexpr Table2Row kTable2[] = {{1, 5.22, 0.48},  {2, 2.65, 0.95},  {5, 1.12, 2.23},
                                 {10, 0.60, 4.14}, {15, 0.43, 5.77}, {20, 0.35, 7.20}};

TEST(RasterScannerTest, Table2HalfExtentMatchesAtThePapersRounding) {
  for (const Table2Row& row : kTable2) {
    const SphereTrajectory traj = SphereTrajectory::paper_trial(row.distance_m);
    const double h = RasterScanner::required_half_extent_deg(traj, 0.0, 0.5);
    // Every row rounds to the printed value except 2 m: 2.6552 -> 2.66 (the
    // paper's 2.65; with Table 1's printed 4.1 cm/s it would be 2.72, so the
    // paper used the column sum 3.3 cm/s and a slightly different rounding).
    const double tol = row.distance_m == 2 ? 0.0055 : 0.005;
    EXPECT_NEAR(h, row.half_extent_deg, tol) << row.distance_m << " m";
  }
}

TEST(RasterScannerTest, Table2FramesPerTrialWithinOneInTheLastDigit) {
  for (const Table2Row& row : kTable2) {
    const SphereTrajectory traj = SphereTrajectory::paper_trial(row.distance_m);
    RasterScannerConfig c;
    c.half_extent_deg = RasterScanner::required_half_extent_deg(traj, 0.0, 0.5);
    const double frames = RasterScanner(c).frames_in(0.5);
    // 1 m and 10-20 m round to the table; 2, 5, 15 m are 0.01-0.015 over it
    // (the paper's frame is 0.1-0.3 % taller than the printed half extent
    // gives: 0.5 s x 10 deg/s / 2h; its rounding of h is the likely cause).
    EXPECT_NEAR(frames, row.frames, 0.016) << row.distance_m << " m";
  }
}

TEST(RasterScannerTest, Table1SpeedsAreTheColumnSums) {
  EXPECT_NEAR(table1_xy_speed_m_s(1), 0.027, 1e-12);
  EXPECT_NEAR(table1_xy_speed_m_s(2), 0.033, 1e-12);  // printed 4.1: a wrong sum
  EXPECT_NEAR(table1_xy_speed_m_s(5), 0.051, 1e-12);
  EXPECT_NEAR(table1_xy_speed_m_s(20), 0.141, 1e-12);
}

}  // namespace
}  // namespace ephor::sphere
