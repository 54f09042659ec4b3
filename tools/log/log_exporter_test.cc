#include "tools/log/log_exporter.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "ephor/shepherd_ground_truth_t.hpp"
#include "ephor/shepherd_objects_t.hpp"

#include "tools/log/repo_schema_for_tests.h"

namespace ephor::logtools {
namespace {

const LcmSchema& schema() { return repo_schema(); }

template <typename T>
void write(lcm::LogFile& log, int64_t t_us, const std::string& channel, const T& msg) {
  std::vector<uint8_t> buf(static_cast<size_t>(msg.getEncodedSize()));
  msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
  lcm::LogEvent e{};
  e.timestamp = t_us;
  e.channel = channel;
  e.datalen = static_cast<int32_t>(buf.size());
  e.data = buf.data();
  ASSERT_EQ(log.writeEvent(&e), 0);
}

ephor::shepherd_objects_t objects(int64_t seq, int n) {
  ephor::shepherd_objects_t m{};
  m.utime = 1000 + seq;
  m.header.sender = "worldmodel";
  m.header.seq = seq;
  m.frame_index = seq;
  for (int i = 0; i < n; ++i) {
    ephor::shepherd_object_t o{};
    o.id = i + 1;
    o.u = static_cast<float>(10 * seq + i);
    m.objects.push_back(o);
  }
  m.num_objects = n;
  return m;
}

// A log like a short run: OBJECTS (seq 0, 1, 3: one missing; 3 has no
// objects), GROUND_TRUTH, and a message of a type we do not know.
std::string make_log() {
  const std::string path = ::testing::TempDir() + "/exporter_" + std::to_string(getpid()) + ".lcm";
  lcm::LogFile log(path, "w");
  EXPECT_TRUE(log.good());
  write(log, 10, "OBJECTS", objects(0, 2));
  ephor::shepherd_ground_truth_t gt{};
  gt.header.sender = "sim";
  gt.num_sheep = 1;
  gt.sheep.resize(1);
  gt.sheep[0].id = 3;
  gt.sheep[0].x_mm = 512.5f;
  gt.sheep[0].visible = true;
  write(log, 20, "GROUND_TRUTH", gt);
  write(log, 30, "OBJECTS", objects(1, 2));
  write(log, 40, "OBJECTS", objects(3, 0));
  lcm::LogEvent foreign{};
  foreign.timestamp = 50;
  foreign.channel = "OBJECTS";
  uint8_t junk[12] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  foreign.datalen = sizeof junk;
  foreign.data = junk;
  EXPECT_EQ(log.writeEvent(&foreign), 0);
  return path;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string line; std::getline(ss, line);) out.push_back(line);
  return out;
}

TEST(LogExporter, CsvHasOneRowPerObjectWithTheMessageFieldsRepeated) {
  const std::string log = make_log();
  std::stringstream out;
  const auto stats = LogExporter(schema(), {"OBJECTS", ExportFormat::kCsv, false}).run(log, out);
  EXPECT_EQ(stats.events, 5);
  EXPECT_EQ(stats.exported, 3);
  EXPECT_EQ(stats.undecodable, 1);
  ASSERT_EQ(stats.first_errors.size(), 1u);
  const auto lines = lines_of(out.str());
  ASSERT_EQ(lines.size(), 1u + 2 + 2 + 1);
  EXPECT_EQ(lines[0].rfind("log_utime_us,channel,utime,header.utime,header.sender,header.seq,"
                           "frame_index,num_objects,objects.id,objects.state,objects.u,",
                           0),
            0u)
      << lines[0];
  EXPECT_EQ(lines[4].rfind("30,OBJECTS,1001,0,worldmodel,1,1,2,2,0,11.0,", 0), 0u) << lines[4];
  // The message without objects still has its row, with empty object columns.
  EXPECT_EQ(lines[5].rfind("40,OBJECTS,1003,0,worldmodel,3,3,0,,,", 0), 0u) << lines[5];
  std::filesystem::remove(log);
}

TEST(LogExporter, JsonLinesCarryChannelTypeAndMessage) {
  const std::string log = make_log();
  std::stringstream out;
  const auto stats =
      LogExporter(schema(), {"GROUND_.*", ExportFormat::kJsonLines, false}).run(log, out);
  EXPECT_EQ(stats.exported, 1);
  const auto lines = lines_of(out.str());
  ASSERT_EQ(lines.size(), 1u);
  const auto j = Json::parse(lines[0]);
  EXPECT_EQ(j["log_utime_us"].get<int64_t>(), 20);
  EXPECT_EQ(j["type"], "ephor.shepherd_ground_truth_t");
  EXPECT_DOUBLE_EQ(j["msg"]["sheep"][0]["x_mm"].get<double>(), 512.5);
  EXPECT_EQ(j["msg"]["sheep"][0]["visible"], true);
  std::filesystem::remove(log);
}

TEST(LogExporter, ASenderThatIsNotUtf8IsExportedWithReplacementCharacters) {
  // Found by the fuzz target lcm_log: a corrupt string made the JSON dump
  // throw and ended the whole export.
  const std::string path =
      ::testing::TempDir() + "/exporter_utf8_" + std::to_string(getpid()) + ".lcm";
  {
    lcm::LogFile log(path, "w");
    ephor::shepherd_objects_t m = objects(0, 1);
    m.header.sender = std::string("wm\x9a\xff");
    write(log, 10, "OBJECTS", m);
  }
  for (const ExportFormat format : {ExportFormat::kJsonLines, ExportFormat::kCsv}) {
    std::ostringstream out;
    const auto stats = LogExporter(schema(), {"OBJECTS", format, false}).run(path, out);
    EXPECT_EQ(stats.exported, 1);
    if (format == ExportFormat::kJsonLines) {
      EXPECT_NE(out.str().find("wm\xef\xbf\xbd"), std::string::npos) << out.str();
    }
  }
  std::remove(path.c_str());
}

TEST(LogExporter, CsvRefusesMixedTypesAndBadInputIsNamed) {
  const std::string log = make_log();
  std::stringstream out;
  EXPECT_THROW(LogExporter(schema(), {".*", ExportFormat::kCsv, false}).run(log, out), ExportError);
  EXPECT_THROW(LogExporter(schema(), {"(", ExportFormat::kCsv, false}).run(log, out), ExportError);
  EXPECT_THROW(LogExporter(schema(), {".*", ExportFormat::kCsv, false}).run("/no/such.lcm", out),
               ExportError);
  std::filesystem::remove(log);
}

TEST(LogSummary, CountsMessagesAndMissingSequenceNumbers) {
  const std::string log = make_log();
  const auto channels = summarize_log(schema(), log);
  ASSERT_EQ(channels.size(), 2u);
  EXPECT_EQ(channels[1].channel, "OBJECTS");
  EXPECT_EQ(channels[1].type, "ephor.shepherd_objects_t");
  EXPECT_EQ(channels[1].count, 4);
  EXPECT_EQ(channels[1].missing, 1);  // seq 2
  EXPECT_EQ(channels[1].undecodable, 1);
  std::stringstream out;
  print_summary(channels, out);
  EXPECT_NE(out.str().find("1 missing by header.seq"), std::string::npos) << out.str();
  std::filesystem::remove(log);
}

TEST(CsvQuote, QuotesOnlyWhenNeeded) {
  EXPECT_EQ(csv_quote("abc"), "abc");
  EXPECT_EQ(csv_quote("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_quote("say \"hi\""), "\"say \"\"hi\"\"\"");
}

}  // namespace
}  // namespace ephor::logtools
