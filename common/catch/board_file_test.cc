#include "common/catch/board_file.h"

#include <cstdio>
#include <limits>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/catch/camera_file.h"
#include "common/config/text_proto.h"

namespace ephor::catching {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kTestdata = EPHOR_CATCH_BOARD_TESTDATA;

const char* kCircles =
    "circle { x_mm: 60 y_mm: 60 diameter_mm: 70 }\n"
    "circle { x_mm: 540 y_mm: 60 diameter_mm: 50 }\n"
    "circle { x_mm: 60 y_mm: 840 diameter_mm: 50 }\n"
    "circle { x_mm: 540 y_mm: 840 diameter_mm: 50 }\n";

std::string board_text(const std::string& sizes, const std::string& circles = kCircles) {
  return sizes + "\n" + circles;
}
const std::string kSizes = "width_mm: 600\nheight_mm: 900\nball_diameter_mm: 40";

// The message of the ConfigError that parsing `text` throws ("" if none).
std::string board_error(const std::string& text) {
  try {
    parse_board_text(text, "b.pbtxt");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}
std::string camera_error(const std::string& text) {
  try {
    parse_camera_text(text, "c.pbtxt");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(BoardFileTest, TestdataBoardIsTheDefaultBoard) {
  const BoardSpec b = load_board_file(kTestdata + "/board.pbtxt");
  const BoardSpec def;
  EXPECT_EQ(b.width_mm, def.width_mm);
  EXPECT_EQ(b.height_mm, def.height_mm);
  EXPECT_EQ(b.ball_diameter_mm, def.ball_diameter_mm);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(b.circles[i].x_mm, def.circles[i].x_mm);
    EXPECT_EQ(b.circles[i].y_mm, def.circles[i].y_mm);
    EXPECT_EQ(b.circles[i].diameter_mm, def.circles[i].diameter_mm);
  }
}

TEST(BoardFileTest, UnreadableFileNamesTheFile) {
  EXPECT_THROW(load_board_file("/nonexistent/board.pbtxt"), std::runtime_error);
  try {
    load_board_file("/nonexistent/board.pbtxt");
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("board file /nonexistent/board.pbtxt: cannot open"));
  }
}

TEST(BoardFileTest, SyntaxErrorGivesTheLine) {
  EXPECT_THAT(board_error("width_mm: 600\nheight_mm: [900\n"), HasSubstr("board file b.pbtxt:2:"));
  EXPECT_THAT(board_error("width_mm: 600\nheigth_mm: 900\n"),
              AllOf(HasSubstr("board file b.pbtxt:2:"), HasSubstr("heigth_mm")));
}

TEST(BoardFileTest, ThreeCirclesAreRefused) {
  const std::string three =
      "circle { x_mm: 60 y_mm: 60 diameter_mm: 70 }\n"
      "circle { x_mm: 540 y_mm: 60 diameter_mm: 50 }\n"
      "circle { x_mm: 60 y_mm: 840 diameter_mm: 50 }\n";
  EXPECT_THAT(board_error(board_text(kSizes, three)),
              AllOf(HasSubstr("board file b.pbtxt: needs exactly 4 circles"), HasSubstr("has 3")));
}

TEST(BoardFileTest, NonPositiveOrNonFiniteSizesAreRefused) {
  EXPECT_THAT(board_error(board_text("width_mm: 0\nheight_mm: 900\nball_diameter_mm: 40")),
              AllOf(HasSubstr("b.pbtxt:1: width_mm"), HasSubstr("positive")));
  EXPECT_THAT(board_error(board_text("width_mm: 600\nheight_mm: -900\nball_diameter_mm: 40")),
              AllOf(HasSubstr("b.pbtxt:2: height_mm"), HasSubstr("-900")));
  EXPECT_THAT(board_error(board_text("width_mm: 600\nheight_mm: 900\nball_diameter_mm: inf")),
              AllOf(HasSubstr("b.pbtxt:3: ball_diameter_mm"), HasSubstr("inf")));
  EXPECT_THAT(board_error(board_text("width_mm: 600\nball_diameter_mm: 40")),
              HasSubstr("height_mm: missing"));
  EXPECT_THAT(board_error(board_text("width_mm: 600\nheight_mm: 900\nball_diameter_mm: 700")),
              HasSubstr("does not fit on the board"));
  const std::string zero =
      "circle { x_mm: 60 y_mm: 60 diameter_mm: 70 }\n"
      "circle { x_mm: 540 y_mm: 60 diameter_mm: 0 }\n"
      "circle { x_mm: 60 y_mm: 840 diameter_mm: 50 }\n"
      "circle { x_mm: 540 y_mm: 840 diameter_mm: 50 }\n";
  EXPECT_THAT(board_error(board_text(kSizes, zero)),
              AllOf(HasSubstr("b.pbtxt:5: circle[1].diameter_mm"), HasSubstr("positive")));
}

TEST(BoardFileTest, CircleOutsideTheBoardIsRefusedByName) {
  const std::string c =
      "circle { x_mm: 60 y_mm: 60 diameter_mm: 70 }\n"
      "circle { x_mm: 540 y_mm: 60 diameter_mm: 50 }\n"
      "circle { x_mm: 60 y_mm: 840 diameter_mm: 50 }\n"
      "circle { x_mm: 590 y_mm: 840 diameter_mm: 50 }\n";
  EXPECT_THAT(board_error(board_text(kSizes, c)),
              AllOf(HasSubstr("b.pbtxt:7: circle[3]"), HasSubstr("bottom-right circle"),
                    HasSubstr("not inside the board")));
}

TEST(BoardFileTest, CirclesOutOfCornerOrderAreRefused) {
  const std::string swapped =
      "circle { x_mm: 540 y_mm: 60 diameter_mm: 50 }\n"
      "circle { x_mm: 60 y_mm: 60 diameter_mm: 70 }\n"
      "circle { x_mm: 60 y_mm: 840 diameter_mm: 50 }\n"
      "circle { x_mm: 540 y_mm: 840 diameter_mm: 50 }\n";
  EXPECT_THAT(board_error(board_text(kSizes, swapped)),
              AllOf(HasSubstr("circle[1]"), HasSubstr("top-right circle is out of order")));
}

TEST(BoardFileTest, WriterRoundTripsAndRefusesABadBoard) {
  BoardSpec b;
  b.circles[3].diameter_mm = 44.5;
  b.ball_diameter_mm = 38.0;
  const std::string text = board_to_text(b, "written by a test\nsecond line");
  EXPECT_THAT(text, HasSubstr("# written by a test\n# second line\n"));
  const BoardSpec back = parse_board_text(text, "mem");
  EXPECT_EQ(back.circles[3].diameter_mm, 44.5);
  EXPECT_EQ(back.ball_diameter_mm, 38.0);

  const std::string path = ::testing::TempDir() + "/catch_board_test_board.pbtxt";
  save_board_file(b, path);
  EXPECT_EQ(load_board_file(path).circles[3].diameter_mm, 44.5);
  std::remove(path.c_str());

  b.circles[0].x_mm = -10.0;
  EXPECT_THROW(save_board_file(b, path), ConfigError);
}

TEST(CameraFileTest, TestdataCamerasLoad) {
  const CameraIntrinsics c = load_camera_file(kTestdata + "/camera.pbtxt");
  EXPECT_EQ(c.width, 640);
  EXPECT_EQ(c.height, 480);
  EXPECT_EQ(c.fy, 601.5);
  ASSERT_EQ(c.distortion.size(), 5u);
  EXPECT_EQ(c.distortion[0], -0.12);
  EXPECT_TRUE(load_camera_file(kTestdata + "/camera_ideal.pbtxt").distortion.empty());
}

TEST(CameraFileTest, EachProblemIsNamed) {
  const std::string ok_tail = "cx: 319.5\ncy: 239.5\n";
  EXPECT_THAT(camera_error("width: 640\nheight: 480\nfx: 0\nfy: 600\n" + ok_tail),
              AllOf(HasSubstr("camera file c.pbtxt:3: fx"), HasSubstr("must be > 0")));
  EXPECT_THAT(camera_error("width: 640\nheight: 480\nfx: 600\nfy: -1\n" + ok_tail),
              AllOf(HasSubstr("c.pbtxt:4: fy"), HasSubstr("must be > 0")));
  EXPECT_THAT(camera_error("width: 0\nheight: 480\nfx: 600\nfy: 600\n" + ok_tail),
              HasSubstr("c.pbtxt:1: width: must be > 0 px, got 0"));
  EXPECT_THAT(camera_error("width: 640\nfx: 600\nfy: 600\n" + ok_tail),
              HasSubstr("height: missing"));
  EXPECT_THAT(camera_error("width: 640\nheight: 480\nfx: nan\nfy: 600\n" + ok_tail),
              AllOf(HasSubstr("c.pbtxt:3: fx"), HasSubstr("finite")));
  EXPECT_THAT(camera_error("width: 640\nheight: 480\nfx: 600\nfy: 600\ncx: 900\ncy: 239.5\n"),
              AllOf(HasSubstr("c.pbtxt:5: cx"), HasSubstr("outside the image")));
  EXPECT_THAT(
      camera_error("width: 640\nheight: 480\nfx: 600\nfy: 600\n" + ok_tail + "distortion: [1, 2]"),
      AllOf(HasSubstr("c.pbtxt:7: distortion[0]"), HasSubstr("got 2")));
  EXPECT_THAT(camera_error("width: 640\nheight: 480\nfx: 600\nfy: 600\n" + ok_tail + "fz: 3\n"),
              AllOf(HasSubstr("camera file c.pbtxt:7:"), HasSubstr("fz")));
  try {
    load_camera_file("/nonexistent/camera.pbtxt");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("camera file /nonexistent/camera.pbtxt: cannot open"));
  }
}

TEST(CameraFileTest, WriterRoundTrips) {
  CameraIntrinsics c;
  c.fx = 812.25;
  c.distortion = {-0.2, 0.05, 0.001, 0.002, -0.01};
  const CameraIntrinsics back = parse_camera_text(camera_to_text(c, "test"), "mem");
  EXPECT_EQ(back.fx, 812.25);
  EXPECT_EQ(back.distortion, c.distortion);
  c.fx = 0.0;
  EXPECT_THROW(save_camera_file(c, ::testing::TempDir() + "/never.pbtxt"), ConfigError);
}

TEST(CameraFileTest, FramesOfAnotherSizeAreNamedWithBothSizes) {
  const CameraIntrinsics c = load_camera_file(kTestdata + "/camera.pbtxt");
  EXPECT_EQ(frame_size_problem(c, "cam.pbtxt", 640, 480, "frames of clip.avi"), "");
  EXPECT_EQ(frame_size_problem(c, "cam.pbtxt", 800, 600, "frames of clip.avi"),
            "frames of clip.avi are 800 x 600 px but the camera file cam.pbtxt says 640 x 480 px");
  // A transposed (portrait) recording is not the same camera either.
  EXPECT_THAT(frame_size_problem(c, "cam.pbtxt", 480, 640, "frames"),
              AllOf(HasSubstr("480 x 640"), HasSubstr("640 x 480")));
}

}  // namespace
}  // namespace ephor::catching
