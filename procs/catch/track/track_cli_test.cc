// ephor-catch-track end to end on a rendered recording, and its answers to
// bad input. The frames are rendered by common/catch/vision's synthetic board
// (ray-cast, anti-aliased, noise sigma 2, the ball 5 grey levels off the
// board) as PNG files of an image sequence, with the board and camera files
// beside them; the tool runs as a process from $EPHOR_BIN_DIR (set by CTest).

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "common/catch/board_file.h"
#include "common/catch/camera_file.h"
#include "common/catch/vision/synthetic_board.h"

namespace ephor::catching {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr double kPi = 3.14159265358979323846;
constexpr double kFps = 60.0;
constexpr int kFrames = 38;
constexpr double kInclineDeg = 25.0;

std::string bin(const std::string& name) {
  const char* dir = std::getenv("EPHOR_BIN_DIR");
  return (dir ? fs::path(dir) : fs::path("bin")) / name;
}

struct CommandResult {
  int status = -1;
  std::string err;
};

CommandResult run(const std::string& args, const fs::path& dir) {
  const fs::path err = dir / "stderr.txt";
  const int raw =
      std::system((bin("ephor-catch-track") + " " + args + " 2>" + err.string()).c_str());
  CommandResult r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::ifstream in(err);
  std::stringstream ss;
  ss << in.rdbuf();
  r.err = ss.str();
  return r;
}

std::vector<nlohmann::json> read_lines(const fs::path& p) {
  std::vector<nlohmann::json> out;
  std::ifstream in(p);
  std::string line;
  while (std::getline(in, line)) out.push_back(nlohmann::json::parse(line));
  return out;
}

// The ball's centre in B at frame k: rolling down the slope from 80 mm with
// 300 mm/s, at 5/7 g sin(incline), and drifting across at 60 mm/s.
Eigen::Vector2d ball_truth(int k) {
  const double t = k / kFps;
  const double a = 5.0 / 7.0 * kGravityMmS2 * std::sin(kInclineDeg * kPi / 180.0);
  return {250.0 + 60.0 * t, 80.0 + 300.0 * t + 0.5 * a * t * t};
}

SyntheticScene scene() {
  SyntheticScene s;
  s.board_to_camera = look_at_board(s.board, 1700.0, 25.0, 15.0, 6.0);
  return s;
}

// A recording: frames/%04d.png, board.pbtxt, camera.pbtxt in a private
// directory, rendered once for all the tests.
class TrackCliTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("catch_track_" + std::to_string(::getpid()));
    fs::create_directories(dir_ / "frames");
    const SyntheticScene s = scene();
    save_board_file(s.board, (dir_ / "board.pbtxt").string());
    save_camera_file(s.camera, (dir_ / "camera.pbtxt").string());
    for (int k = 0; k < kFrames; ++k) {
      SyntheticScene f = s;
      f.ball = SyntheticBall{ball_truth(k), 5.0};
      char name[32];
      std::snprintf(name, sizeof name, "%04d.png", k);
      ASSERT_TRUE(cv::imwrite((dir_ / "frames" / name).string(),
                              render_board(f, 2.0, 100 + static_cast<uint64_t>(k))));
    }
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static std::string frames() { return "'" + (dir_ / "frames" / "%04d.png").string() + "'"; }
  static std::string files(const fs::path& board, const fs::path& camera) {
    return " --board " + board.string() + " --camera " + camera.string() + " --fps 60";
  }
  static std::string good_files() { return files(dir_ / "board.pbtxt", dir_ / "camera.pbtxt"); }

  static fs::path dir_;
};
fs::path TrackCliTest::dir_;

TEST_F(TrackCliTest, CameraPoseAndBallPositionsAgreeWithTheTruth) {
  const fs::path out = dir_ / "track.jsonl";
  const CommandResult r =
      run(frames() + good_files() + " --incline-deg 25 --json " + out.string(), dir_);
  ASSERT_EQ(r.status, 0) << r.err;
  const std::vector<nlohmann::json> lines = read_lines(out);
  ASSERT_EQ(lines.size(), static_cast<size_t>(kFrames + 1));

  // The camera's pose: within 1 mm and 0.1 deg of the rendering's.
  const Pose truth = scene().board_to_camera;
  const nlohmann::json& pose = lines[0].at("camera_pose");
  ASSERT_EQ(pose.at("R").size(), 9u);
  ASSERT_EQ(pose.at("t_mm").size(), 3u);
  Eigen::Matrix3d r_est;
  Eigen::Vector3d t_est;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r_est(i, j) = pose.at("R")[static_cast<size_t>(3 * i + j)];
    t_est(i) = pose.at("t_mm")[static_cast<size_t>(i)];
  }
  const double angle_deg =
      Eigen::AngleAxisd(r_est * truth.linear().transpose()).angle() * 180.0 / kPi;
  std::cerr << "camera pose error " << (t_est - truth.translation()).norm() << " mm, " << angle_deg
            << " deg\n";
  EXPECT_LT(angle_deg, 0.1);
  EXPECT_LT((t_est - truth.translation()).norm(), 1.0)
      << "t " << t_est.transpose() << " truth " << truth.translation().transpose();

  // The ball: found on the board in most frames once there are two frames
  // to difference, within a few mm of the truth.
  int tracked = 0, close = 0;
  std::vector<double> errors;
  for (int k = 0; k < kFrames; ++k) {
    const nlohmann::json& f = lines[static_cast<size_t>(k + 1)];
    EXPECT_EQ(f.at("frame"), k);
    EXPECT_NEAR(f.at("t").get<double>(), k / kFps, 1e-9);
    if (k < 4) continue;  // differencing needs frame k-2, the filter a second point
    if (f.at("ball_mm").is_null()) continue;
    ++tracked;
    const Eigen::Vector2d p(f.at("ball_mm")[0].get<double>(), f.at("ball_mm")[1].get<double>());
    const double e = (p - ball_truth(k)).norm();
    errors.push_back(e);
    if (e < 4.0) ++close;
  }
  std::sort(errors.begin(), errors.end());
  ASSERT_FALSE(errors.empty());
  std::cerr << "tracked " << tracked << " of " << kFrames - 4 << " frames; error median "
            << errors[errors.size() / 2] << " mm, max " << errors.back() << " mm\n";
  EXPECT_GE(tracked, (kFrames - 4) * 9 / 10);
  EXPECT_GE(close, (kFrames - 4) * 8 / 10);
  EXPECT_LT(errors[errors.size() / 2], 2.5);
}

TEST_F(TrackCliTest, FramesOfAnotherSizeThanTheCameraFileAreRefusedNamingBothSizes) {
  CameraIntrinsics big = scene().camera;
  big.width = 800;
  big.height = 600;
  big.cx = 399.5;
  big.cy = 299.5;
  const fs::path camera = dir_ / "camera_800.pbtxt";
  save_camera_file(big, camera.string());
  const fs::path out = dir_ / "never.jsonl";
  const CommandResult r =
      run(frames() + files(dir_ / "board.pbtxt", camera) + " --json " + out.string(), dir_);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_THAT(r.err,
              AllOf(HasSubstr("640 x 480"), HasSubstr("800 x 600"), HasSubstr(camera.string())));
  EXPECT_FALSE(fs::exists(out));  // nothing written
}

TEST_F(TrackCliTest, ABoardFileWithThreeCirclesIsRefusedNamingTheFile) {
  const fs::path board = dir_ / "three.pbtxt";
  std::ofstream(board) << "width_mm: 600 height_mm: 900 ball_diameter_mm: 40\n"
                          "circle { x_mm: 60 y_mm: 60 diameter_mm: 70 }\n"
                          "circle { x_mm: 540 y_mm: 60 diameter_mm: 50 }\n"
                          "circle { x_mm: 60 y_mm: 840 diameter_mm: 50 }\n";
  const CommandResult r = run(frames() + files(board, dir_ / "camera.pbtxt") + " --json -", dir_);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, AllOf(HasSubstr("board file " + board.string()),
                           HasSubstr("needs exactly 4 circles"), HasSubstr("has 3")));
}

TEST_F(TrackCliTest, ACoveredCircleIsNamedWithWhereItWasLookedFor) {
  // Ten frames of the board with the bottom-left circle painted over.
  const fs::path covered = dir_ / "covered";
  fs::create_directories(covered);
  SyntheticScene s = scene();
  s.covered_circles = {2};
  for (int k = 0; k < 10; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "%04d.png", k);
    ASSERT_TRUE(cv::imwrite((covered / name).string(),
                            render_board(s, 2.0, 300 + static_cast<uint64_t>(k))));
  }
  const std::string video = "'" + (covered / "%04d.png").string() + "'";
  // The operator's windows: 60 px squares around where the circles are.
  std::string windows;
  for (int i = 0; i < 4; ++i) {
    const BoardCircle& c = s.board.circles[static_cast<size_t>(i)];
    const Eigen::Vector2d p =
        project_pinhole(s.camera, s.board_to_camera, Eigen::Vector3d(c.x_mm, c.y_mm, 0.0));
    const int u = static_cast<int>(std::lround(p.x())), v = static_cast<int>(std::lround(p.y()));
    windows += (i ? ";" : "") + std::to_string(u - 30) + "," + std::to_string(v - 30) + "," +
               std::to_string(u + 29) + "," + std::to_string(v + 29);
  }
  const CommandResult w =
      run(video + good_files() + " --circle-windows '" + windows + "' --json -", dir_);
  EXPECT_EQ(w.status, 1);
  EXPECT_THAT(w.err, AllOf(HasSubstr("circle bottom-left not found: looked in window ("),
                           HasSubstr("frames 0-9")));
  const CommandResult a = run(video + good_files() + " --json -", dir_);
  EXPECT_EQ(a.status, 1);
  EXPECT_THAT(a.err, AllOf(HasSubstr("bottom-left"),
                           HasSubstr("in the whole 640 x 480 image and found 3")));
}

TEST_F(TrackCliTest, AVideoThatCannotBeReadAndBadFlagsAreRefused) {
  const CommandResult r = run((dir_ / "nothing.avi").string() + good_files() + " --json -", dir_);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("nothing.avi': no such file"));
  EXPECT_EQ(run(frames() + good_files() + " --json - --fps 0", dir_).status, 2);
  EXPECT_EQ(run(frames() + good_files() + " --json - --circle-windows 1,2,3", dir_).status, 2);
}

}  // namespace
}  // namespace ephor::catching
