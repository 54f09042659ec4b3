#include "common/calibration/field_calibration.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/config/text_proto.h"

namespace ephor::calibration {
namespace {

using ::testing::HasSubstr;

AffineMap known_map() {
  AffineMap m;
  m << 2.5, 0.1, -620.0,  //
      -0.05, -2.6, 1090.0;
  return m;
}

Correspondence through(const AffineMap& m, double u, double v) {
  return {{u, v}, m * Eigen::Vector3d(u, v, 1.0)};
}

TEST(FieldCalibrationTest, FitFromThreeExactPointsRecoversTheMatrix) {
  const AffineMap m = known_map();
  const auto cal = FieldCalibration::fit(
      {through(m, 10, 20), through(m, 500, 30), through(m, 250, 470)}, {through(m, 100, 100)});
  EXPECT_LT((cal.matrix(Plane::kObject) - m).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(FieldCalibrationTest, FitFromManyNoisyPointsIsLeastSquares) {
  const AffineMap m = known_map();
  std::vector<Correspondence> pts;
  // Alternating +-0.5 mm error: least squares averages it out.
  int k = 0;
  for (double u : {0.0, 128.0, 256.0, 384.0, 511.0})
    for (double v : {0.0, 160.0, 320.0, 481.0}) {
      auto c = through(m, u, v);
      c.field_mm.x() += (k++ % 2 == 0) ? 0.5 : -0.5;
      pts.push_back(c);
    }
  const auto cal = FieldCalibration::fit(pts, {pts[3]});
  for (const auto& c : pts) {
    const Eigen::Vector2d exact = m * Eigen::Vector3d(c.image_px.x(), c.image_px.y(), 1.0);
    EXPECT_LT((cal.image_to_field(c.image_px.x(), c.image_px.y(), Plane::kObject) - exact).norm(),
              0.5);
  }
}

TEST(FieldCalibrationTest, FourthPointGivesThePerspectiveElevationPlane) {
  // Three corners in the object plane and one point in the elevation plane,
  // as the paper takes them; compare with the true pinhole camera everywhere.
  const geometry::OverheadCamera cam;
  const geometry::Workcell cell;
  const double zo = cell.object_plane_z_mm;
  const double ze = cell.elevation_plane_z_mm;
  const auto obj = [&](double x, double y) {
    return Correspondence{cam.project(x, y, zo), {x, y}};
  };
  const Correspondence fourth{cam.project(1100.0, 800.0, ze), {1100.0, 800.0}};
  const auto cal = FieldCalibration::fit({obj(0, 0), obj(1219, 0), obj(0, 914)}, {fourth});
  double worst_mm = 0.0;
  for (double x = 0.0; x <= 1219.0; x += 100.0)
    for (double y = 0.0; y <= 914.0; y += 100.0) {
      const Eigen::Vector2d p = cam.project(x, y, ze);
      worst_mm = std::max(
          worst_mm,
          (cal.image_to_field(p.x(), p.y(), Plane::kElevation) - Eigen::Vector2d(x, y)).norm());
    }
  EXPECT_LT(worst_mm, 1e-6);
  // And the two planes really differ at the field's edge (perspective).
  const Eigen::Vector2d corner = cam.project(0.0, 0.0, zo);
  EXPECT_GT((cal.image_to_field(corner.x(), corner.y(), Plane::kObject) -
             cal.image_to_field(corner.x(), corner.y(), Plane::kElevation))
                .norm(),
            30.0);
}

TEST(FieldCalibrationTest, ThreeElevationPointsFitTheirOwnAffine) {
  AffineMap e = known_map();
  e(0, 2) += 7.0;
  const AffineMap m = known_map();
  const auto cal =
      FieldCalibration::fit({through(m, 0, 0), through(m, 500, 0), through(m, 0, 480)},
                            {through(e, 0, 0), through(e, 500, 0), through(e, 0, 480)});
  EXPECT_LT((cal.matrix(Plane::kElevation) - e).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(FieldCalibrationTest, ImageToFieldToImageRoundTrips) {
  const auto cal = FieldCalibration::from_camera({}, {});
  for (Plane plane : {Plane::kObject, Plane::kElevation})
    for (double u = 0.0; u < 512.0; u += 37.0)
      for (double v = 0.0; v < 482.0; v += 41.0) {
        const Eigen::Vector2d f = cal.image_to_field(u, v, plane);
        const Eigen::Vector2d back = cal.field_to_image(f.x(), f.y(), plane);
        EXPECT_NEAR(back.x(), u, 1e-9);
        EXPECT_NEAR(back.y(), v, 1e-9);
      }
}

TEST(FieldCalibrationTest, FitRejectsTooFewOrCollinearPoints) {
  const AffineMap m = known_map();
  EXPECT_THROW(FieldCalibration::fit({through(m, 0, 0), through(m, 1, 1)}, {through(m, 5, 5)}),
               std::invalid_argument);
  try {
    FieldCalibration::fit({through(m, 0, 0), through(m, 10, 10), through(m, 20, 20)},
                          {through(m, 5, 5)});
    FAIL() << "collinear points accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("collinear"));
  }
  EXPECT_THROW(
      FieldCalibration::fit({through(m, 0, 0), through(m, 500, 0), through(m, 0, 480)}, {}),
      std::invalid_argument);
}

TEST(FieldCalibrationTest, SaveThenLoadGivesTheSameCalibration) {
  const auto cal = FieldCalibration::from_camera({}, {});
  const std::string path =
      (std::filesystem::temp_directory_path() / "ephor_calibration_test_roundtrip.pbtxt").string();
  cal.save(path, "test file\nsecond line");
  const auto back = FieldCalibration::load(path);
  std::filesystem::remove(path);
  EXPECT_EQ(back.matrix(Plane::kObject), cal.matrix(Plane::kObject));
  EXPECT_EQ(back.matrix(Plane::kElevation), cal.matrix(Plane::kElevation));
  EXPECT_EQ(back.plane_z_mm(Plane::kElevation), cal.plane_z_mm(Plane::kElevation));
  EXPECT_EQ(back.object_points().size(), 4u);
  EXPECT_EQ(back.elevation_points().size(), 4u);
}

// A valid file, with one line replaced to make it bad.
std::string good_text() {
  return "object_plane { t11: 1.6 t12: 0 t13: -100\n"
         "               t21: 0 t22: -1.6 t23: 900 }\n"
         "elevation_plane { t11: 1.5 t12: 0 t13: -90\n"
         "                  t21: 0 t22: -1.5 t23: 880 }\n"
         "object_plane_z_mm: 30\n"
         "elevation_plane_z_mm: 200\n";
}

std::string load_error(const std::string& text) {
  try {
    FieldCalibration::parse(text, "cal.pbtxt");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(FieldCalibrationTest, GoodTextLoads) {
  const auto cal = FieldCalibration::parse(good_text(), "cal.pbtxt");
  EXPECT_DOUBLE_EQ(cal.image_to_field(100, 100, Plane::kObject).x(), 60.0);
}

TEST(FieldCalibrationTest, NanIsRejectedWithFileLineAndField) {
  std::string t = good_text();
  t.replace(t.find("t13: -100"), 9, "t13: nan");
  EXPECT_EQ(load_error(t), "cal.pbtxt:1: object_plane.t13: must be a finite number, got nan");
}

TEST(FieldCalibrationTest, MissingElementIsRejected) {
  std::string t = good_text();
  t.replace(t.find("t22: -1.5"), 9, "");
  EXPECT_EQ(load_error(t), "cal.pbtxt:3: elevation_plane.t22: missing");
}

TEST(FieldCalibrationTest, MissingPlaneOrHeightIsRejected) {
  EXPECT_THAT(load_error("object_plane_z_mm: 30\n"), HasSubstr("object_plane: missing"));
  std::string t = good_text();
  t.replace(t.find("elevation_plane_z_mm: 200"), 25, "");
  EXPECT_THAT(load_error(t), HasSubstr("elevation_plane_z_mm: missing"));
}

TEST(FieldCalibrationTest, SingularMatrixIsRejected) {
  std::string t = good_text();
  // Second row = first row: every image point lands on a line in the field.
  t.replace(t.find("t21: 0 t22: -1.6 t23: 900"), 25, "t21: 1.6 t22: 0 t23: 900");
  EXPECT_THAT(load_error(t), HasSubstr("cal.pbtxt:1: object_plane: singular matrix"));
}

TEST(FieldCalibrationTest, SyntaxErrorAndMissingFileNameTheFile) {
  EXPECT_THAT(load_error("object_plane { t11: }"), HasSubstr("cal.pbtxt:1:"));
  EXPECT_THAT(load_error("bogus_field: 3"), HasSubstr("bogus_field"));
  try {
    FieldCalibration::load("/nonexistent/cal.pbtxt");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("/nonexistent/cal.pbtxt: cannot open"));
  }
}

std::string source_dir() {
  const char* env = std::getenv("EPHOR_SOURCE_DIR");
  return env != nullptr ? env : EPHOR_SOURCE_DIR_DEFAULT;
}

TEST(SimCalibrationTest, DeployedFileAgreesWithTheSimCameraOverTheField) {
  const auto cal = FieldCalibration::load(source_dir() + "/deploy/calibration/sim.pbtxt");
  const geometry::OverheadCamera cam;
  const geometry::Workcell cell;
  double worst_mm = 0.0;
  for (Plane plane : {Plane::kObject, Plane::kElevation}) {
    const double z = cal.plane_z_mm(plane);
    EXPECT_EQ(z, plane == Plane::kObject ? cell.object_plane_z_mm : cell.elevation_plane_z_mm);
    for (double x = 0.0; x <= cell.field_length_mm; x += 20.0)
      for (double y = 0.0; y <= cell.field_width_mm; y += 20.0) {
        const Eigen::Vector2d p = cam.project(x, y, z);
        worst_mm = std::max(
            worst_mm, (cal.image_to_field(p.x(), p.y(), plane) - Eigen::Vector2d(x, y)).norm());
      }
  }
  EXPECT_LT(worst_mm, 0.5);
}

TEST(SimCalibrationTest, InterpolatedPlaneFitsTheSheepMarkHeight) {
  const auto cal = FieldCalibration::from_camera({}, {});
  const geometry::OverheadCamera cam;
  const double z = 52.0;  // the simulator's mark height, between the two planes
  for (double x : {0.0, 600.0, 1219.0})
    for (double y : {0.0, 914.0}) {
      const Eigen::Vector2d p = cam.project(x, y, z);
      EXPECT_LT((cal.image_to_field_at_height(p.x(), p.y(), z) - Eigen::Vector2d(x, y)).norm(),
                1e-6);
    }
}

}  // namespace
}  // namespace ephor::calibration
