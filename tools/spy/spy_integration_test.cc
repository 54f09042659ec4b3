// tools/ephor spy under a virtual display (Xvfb) next to a live publisher of
// our types: lcm-spy, started by our launcher script with our types jar,
// must decode OBJECTS, GROUND_TRUTH and CAMERA into our classes with the
// values that were published. The check reads lcm-spy's own channel table
// and decoded objects (tools/spy/EphorSpyProbe.java); pictures of its windows
// are kept in the build tree (test-artifacts/spy/) for people to look at.

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>

#include "common/lcm/bus.h"
#include "ephor/camera_frame_t.hpp"
#include "ephor/shepherd_ground_truth_t.hpp"
#include "ephor/shepherd_objects_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

using std::chrono::seconds;

constexpr const char* kUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=16777216";

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::optional<launcher::ExitInfo> exit_of(const Processes& p, const std::string& name) {
  for (const auto& e : p.exits())
    if (e.name == name) return e;
  return std::nullopt;
}

TEST(Spy, DecodesOurTypesFromALivePublisher) {
  const std::string bin_dir = std::filesystem::path(bin("ephor-launch")).parent_path().string();
  const std::string build_dir = std::filesystem::path(bin_dir).parent_path().string();
  const std::string out = build_dir + "/test-artifacts/spy";
  std::filesystem::remove_all(out);

  Processes p;
  // Xvfb picks a free display and writes its number to fd 1.
  p.start("xvfb", "/usr/bin/Xvfb",
          {"-displayfd", "1", "-screen", "0", "1280x800x24", "-nolisten", "tcp"});
  std::string display;
  ASSERT_TRUE(wait_until(
      [&] {
        for (const auto& l : p.lines("xvfb"))
          if (!l.empty() && std::isdigit(static_cast<unsigned char>(l[0]))) display = ":" + l;
        return !display.empty();
      },
      seconds(20)))
      << "Xvfb did not start";

  // A live publisher: objects, ground truth and small camera frames at 20 Hz.
  std::atomic<bool> stop{false};
  std::thread publisher([&] {
    Bus bus(kUrl, "spy_test");
    int64_t frame = 0;
    while (!stop) {
      shepherd_objects_t o{};
      o.utime = 1'700'000'000'000'000 + frame * 50'000;
      o.frame_index = 1000 + frame;
      shepherd_object_t obj{};
      obj.id = 42;
      obj.u = 123.5f;
      obj.v = 456.25f;
      o.objects = {obj};
      o.num_objects = 1;
      bus.publish("OBJECTS", o);
      shepherd_ground_truth_t gt{};
      gt.utime = o.utime;
      gt.frame_index = o.frame_index;
      gt.sheep.resize(2);
      gt.num_sheep = 2;
      bus.publish("GROUND_TRUTH", gt);
      camera_frame_t f{};
      f.utime = o.utime;
      f.width = 64;
      f.height = 48;
      f.size = 64 * 48;
      f.data.assign(static_cast<size_t>(f.size), 128);
      bus.publish("CAMERA", f);
      ++frame;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the publisher's rate
    }
  });

  p.start("spy", source_path("tools/ephor.d/spy"),
          {"--check", out, "--timeout-s", "60", "OBJECTS", "GROUND_TRUTH", "CAMERA"},
          {{"DISPLAY", display},
           {"LCM_DEFAULT_URL", kUrl},
           {"EPHOR_ROOT", source_path("")},
           {"EPHOR_BUILD_DIR", build_dir}});
  const bool finished = wait_until([&] { return exit_of(p, "spy").has_value(); }, seconds(120));
  stop = true;
  publisher.join();
  ASSERT_TRUE(finished) << "lcm-spy probe did not finish";
  std::string log;
  for (const auto& l : p.lines("spy")) log += l + "\n";
  ASSERT_EQ(exit_of(p, "spy")->code, 0) << log;

  // lcm-spy's channel table names our classes, with no undecodable messages.
  const std::string table = read_file(out + "/channels.txt");
  EXPECT_NE(table.find("OBJECTS\tephor.shepherd_objects_t\t"), std::string::npos) << table;
  EXPECT_NE(table.find("GROUND_TRUTH\tephor.shepherd_ground_truth_t\t"), std::string::npos)
      << table;
  EXPECT_NE(table.find("CAMERA\tephor.camera_frame_t\t"), std::string::npos) << table;
  // Its decoded message carries what we published.
  const std::string objects = read_file(out + "/OBJECTS.txt");
  EXPECT_NE(objects.find("header.sender = spy_test"), std::string::npos) << objects;
  EXPECT_NE(objects.find("objects[0].id = 42"), std::string::npos) << objects;
  EXPECT_NE(objects.find("objects[0].u = 123.5"), std::string::npos) << objects;
  EXPECT_NE(objects.find("frame_index = 1"), std::string::npos) << objects;
  for (const char* png : {"spy.png", "viewer.png"}) {
    ASSERT_TRUE(std::filesystem::exists(out + "/" + png)) << png;
    EXPECT_GT(std::filesystem::file_size(out + "/" + png), 2000u) << png;
  }
  std::cout << "[ artifacts   ] " << out << "\n" << table;
}

}  // namespace
}  // namespace ephor::testing
