#include "tools/log/message_decoder.h"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "ephor/camera_frame_t.hpp"
#include "ephor/shepherd_objects_t.hpp"
#include "ephor/task_jobs_t.hpp"

#include "tools/log/repo_schema_for_tests.h"

namespace ephor::logtools {
namespace {

const LcmSchema& schema() { return repo_schema(); }

template <typename T>
std::vector<uint8_t> encode(const T& msg) {
  std::vector<uint8_t> buf(static_cast<size_t>(msg.getEncodedSize()));
  msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
  return buf;
}

ephor::shepherd_objects_t two_objects() {
  ephor::shepherd_objects_t m;
  m.utime = 1700000000123456;
  m.header.utime = 1700000000124000;
  m.header.sender = "worldmodel";
  m.header.seq = 41;
  m.frame_index = 1234;
  for (int i = 0; i < 2; ++i) {
    ephor::shepherd_object_t o{};
    o.id = 7 + i;
    o.state = static_cast<int8_t>(i == 0 ? ephor::shepherd_object_t::STATE_VISIBLE
                                         : ephor::shepherd_object_t::STATE_OBSCURED);
    o.u = 100.5f + static_cast<float>(i);
    o.v = -3.25f;
    o.x_mm = 812.0f;
    o.y_mm = 402.46573f;
    o.vx_mm_s = -12.5f;
    o.area = 200 + i;
    m.objects.push_back(o);
  }
  m.num_objects = 2;
  return m;
}

TEST(MessageDecoder, DecodesNestedStructsArraysAndSignedValues) {
  const auto buf = encode(two_objects());
  const auto msg = MessageDecoder(schema()).decode(buf.data(), buf.size());
  ASSERT_NE(msg.type, nullptr);
  EXPECT_EQ(msg.type->full_name(), "ephor.shepherd_objects_t");
  const Json& j = msg.fields;
  EXPECT_EQ(j["utime"].get<int64_t>(), 1700000000123456);
  EXPECT_EQ(j["header"]["sender"], "worldmodel");
  EXPECT_EQ(j["header"]["seq"].get<int64_t>(), 41);
  ASSERT_EQ(j["objects"].size(), 2u);
  EXPECT_EQ(j["objects"][1]["id"].get<int>(), 8);
  EXPECT_EQ(j["objects"][1]["state"].get<int>(), int{ephor::shepherd_object_t::STATE_OBSCURED});
  EXPECT_DOUBLE_EQ(j["objects"][1]["u"].get<double>(), 101.5);
  EXPECT_DOUBLE_EQ(j["objects"][0]["v"].get<double>(), -3.25);
  EXPECT_DOUBLE_EQ(j["objects"][0]["vx_mm_s"].get<double>(), -12.5);
  // Floats print with the digits a float has, not a double's.
  EXPECT_EQ(j["objects"][0]["x_mm"].dump(), "812.0");
  EXPECT_EQ(j["objects"][0]["y_mm"].dump(), "402.46573");
  // Declaration order is kept (CSV columns and readers rely on it).
  EXPECT_EQ(j.begin().key(), "utime");
}

TEST(MessageDecoder, StringsBooleansAndNonFiniteFloats) {
  ephor::task_jobs_t m{};
  m.host = "planning";
  m.process = "vision";
  m.task = "";
  m.rt_granted = true;
  m.rt_error = "EPERM, \"quoted\"";
  ephor::task_job_t job{};
  job.exec_us = 1234;
  job.deadline_met = false;
  m.jobs = {job, job};
  m.num_jobs = 2;
  const auto buf = encode(m);
  const Json j = MessageDecoder(schema()).decode(buf.data(), buf.size()).fields;
  EXPECT_EQ(j["process"], "vision");
  EXPECT_EQ(j["task"], "");
  EXPECT_EQ(j["rt_granted"], true);
  EXPECT_EQ(j["rt_error"], "EPERM, \"quoted\"");
  EXPECT_EQ(j["jobs"][1]["exec_us"].get<int>(), 1234);
  EXPECT_EQ(j["jobs"][1]["deadline_met"], false);

  auto objects = two_objects();
  objects.objects[0].u = std::numeric_limits<float>::quiet_NaN();
  const auto obuf = encode(objects);
  EXPECT_EQ(MessageDecoder(schema()).decode(obuf.data(), obuf.size()).fields["objects"][0]["u"],
            "nan");
}

TEST(MessageDecoder, ByteArraysAreSummarisedUnlessAskedFor) {
  ephor::camera_frame_t f{};
  f.width = 4;
  f.height = 2;
  f.size = 8;
  f.data = {0, 1, 2, 3, 250, 251, 252, 255};
  const auto buf = encode(f);
  EXPECT_EQ(MessageDecoder(schema()).decode(buf.data(), buf.size()).fields["data"], "<8 bytes>");
  const Json full = MessageDecoder(schema(), {true}).decode(buf.data(), buf.size()).fields;
  ASSERT_EQ(full["data"].size(), 8u);
  EXPECT_EQ(full["data"][7].get<int>(), 255);
}

TEST(MessageDecoder, BrokenMessagesGiveAClearError) {
  auto buf = encode(two_objects());
  const MessageDecoder d(schema());
  // Truncated in the middle of the objects.
  try {
    d.decode(buf.data(), buf.size() - 10);
    FAIL() << "no error";
  } catch (const DecodeError& e) {
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
  // Extra bytes after the last field.
  auto longer = buf;
  longer.push_back(0);
  EXPECT_THROW(d.decode(longer.data(), longer.size()), DecodeError);
  // A foreign type (fingerprint of nothing we know).
  auto foreign = buf;
  foreign[0] ^= 0xff;
  try {
    d.decode(foreign.data(), foreign.size());
    FAIL() << "no error";
  } catch (const DecodeError& e) {
    EXPECT_NE(std::string(e.what()).find("fingerprint"), std::string::npos) << e.what();
  }
  EXPECT_THROW(d.decode(buf.data(), 4), DecodeError);
  // A negative array size (num_objects = -1) is refused, not allocated.
  auto negative = encode(ephor::shepherd_objects_t{});
  for (size_t i = negative.size() - 4; i < negative.size(); ++i) negative[i] = 0xff;
  EXPECT_THROW(d.decode(negative.data(), negative.size()), DecodeError);
}

}  // namespace
}  // namespace ephor::logtools
