#include "procs/shepherd/planner/recorded_start.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace ephor::planner {
namespace {

// A row as `tools/ephor log export --channel GROUND_TRUTH --json` writes it
// (fields the reader does not use trimmed).
const char* kRow =
    R"({"log_utime_us":1,"channel":"GROUND_TRUTH","type":"ephor.shepherd_ground_truth_t","msg":{)"
    R"("num_sheep":2,"sheep":[)"
    R"({"id":1,"x_mm":850.5,"y_mm":746.25,"heading_rad":3.14159265358979,"speed_mm_s":30.0,"on_field":true},)"
    R"({"id":2,"x_mm":-20.0,"y_mm":100.0,"heading_rad":0.0,"speed_mm_s":30.0,"on_field":false}]}})";

TEST(RecordedStart, SheepOnTheFieldWithTheirVelocity) {
  const auto sheep = sheep_from_ground_truth_row(kRow);
  ASSERT_EQ(sheep.size(), 1u);  // sheep 2 has left the field
  EXPECT_EQ(sheep[0].id, 1);
  EXPECT_DOUBLE_EQ(sheep[0].x_mm, 850.5);
  EXPECT_DOUBLE_EQ(sheep[0].y_mm, 746.25);
  EXPECT_NEAR(sheep[0].vx_mm_s, -30.0, 1e-9);  // heading pi: moving toward -x
  EXPECT_NEAR(sheep[0].vy_mm_s, 0.0, 1e-9);
}

std::string error_of(const std::string& line) {
  try {
    sheep_from_ground_truth_row(line);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(RecordedStart, BadRowsAreRefusedNamingTheProblem) {
  EXPECT_NE(error_of("garbage").find("not a JSON object"), std::string::npos);
  EXPECT_NE(error_of(R"({"msg":{"blobs":[]}})").find("no msg.sheep"), std::string::npos);
  // JSON has no NaN: a NaN in the message is exported as null.
  EXPECT_NE(error_of(R"({"msg":{"sheep":[{"id":3,"x_mm":null,"y_mm":1,"heading_rad":0,)"
                     R"("speed_mm_s":30}]}})")
                .find("sheep 3: x_mm"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"msg":{"sheep":[{"id":4,"x_mm":1,"y_mm":1,"heading_rad":0}]}})")
                .find("sheep 4: speed_mm_s"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"msg":{"sheep":[]}})").find("no sheep on the field"), std::string::npos);
}

TEST(RecordedStart, AMissingFileIsNamed) {
  try {
    sheep_from_ground_truth_file("/no/such/ground_truth.jsonl");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("/no/such/ground_truth.jsonl"), std::string::npos);
  }
}

}  // namespace
}  // namespace ephor::planner
