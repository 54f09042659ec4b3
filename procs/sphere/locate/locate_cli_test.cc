// ephor-sphere-scan -> ephor-sphere-locate end to end, and the locator's
// answers to bad input: a letter in a row (exit 2 naming the line), a window
// with no sphere ("no estimate" with its reason), a bad flag (exit 2).
// Runs the built executables from $EPHOR_BIN_DIR (set by CTest).

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace {

namespace fs = std::filesystem;

std::string bin(const std::string& name) {
  const char* dir = std::getenv("EPHOR_BIN_DIR");
  return (dir ? fs::path(dir) : fs::path("bin")) / name;
}

struct CommandResult {
  int status = -1;
  std::string err;
};

CommandResult run(const std::string& cmd, const fs::path& dir) {
  const fs::path err = dir / "stderr.txt";
  const int raw = std::system((cmd + " 2>" + err.string()).c_str());
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

class LocateCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("sphere_locate_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(LocateCliTest, SimulatedTrialsAreLocatedAndAnEmptyWindowSaysWhy) {
  const fs::path scan = dir_ / "scan.csv", truth = dir_ / "truth.jsonl", out = dir_ / "out.jsonl";
  ASSERT_EQ(run(bin("ephor-sphere-scan") +
                    " --distance-m 5 --seed 3 --trials 2 --background-below-deg 0 --out " +
                    scan.string() + " --truth " + truth.string(),
                dir_)
                .status,
            0);
  {  // a third window with nothing but misses
    std::ofstream app(scan, std::ios::app);
    for (int k = 0; k < 50; ++k)
      app << 1.0 + 0.001 * k << "," << 5000 + k / 10 << ",0.001,0.002,nan\n";
  }
  for (const char* algorithm : {"sle", "fit"}) {
    const CommandResult r = run(bin("ephor-sphere-locate") + " " + scan.string() + " --algorithm " +
                                    algorithm + " --json " + out.string(),
                                dir_);
    ASSERT_EQ(r.status, 0) << r.err;
    const std::vector<nlohmann::json> lines = read_lines(out);
    const std::vector<nlohmann::json> truths = read_lines(truth);
    ASSERT_EQ(lines.size(), 3u);
    for (int k = 0; k < 2; ++k) {
      const nlohmann::json& j = lines[static_cast<size_t>(k)];
      ASSERT_TRUE(j.contains("position_m")) << j.dump();
      const double t =
          j["t_s"].get<double>() - truths[static_cast<size_t>(k)]["t0_s"].get<double>();
      for (int a = 0; a < 3; ++a) {
        const double truth_a = truths[static_cast<size_t>(k)]["position_m"][a].get<double>() +
                               truths[static_cast<size_t>(k)]["velocity_m_s"][a].get<double>() * t;
        EXPECT_NEAR(j["position_m"][a].get<double>(), truth_a, 0.01) << algorithm << " axis " << a;
      }
      EXPECT_GT(j["points"].get<int>(), 1000);
    }
    EXPECT_EQ(lines[2]["estimate"], "no estimate");
    EXPECT_EQ(lines[2]["reason"], "no returns closer than the background threshold");
  }
}

TEST_F(LocateCliTest, ALetterInARowIsRefusedWithItsLineNumber) {
  const fs::path scan = dir_ / "bad.csv";
  std::ofstream(scan)
      << "t_s,line,azimuth_rad,elevation_rad,range_m\n0,0,0.01,0,5\n0.0001,0,0.01,0,5x\n";
  const CommandResult r =
      run(bin("ephor-sphere-locate") + " " + scan.string() + " --algorithm sle --json -", dir_);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("bad.csv:3: range_m '5x' is not a finite number"), std::string::npos)
      << r.err;
}

TEST_F(LocateCliTest, ABadFlagExitsWithTwo) {
  const CommandResult r =
      run(bin("ephor-sphere-locate") + " x.csv --algorithm ransac --json -", dir_);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--algorithm"), std::string::npos) << r.err;
}

}  // namespace
