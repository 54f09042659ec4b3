#include "common/geometry/workcell_file.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"

namespace ephor::geometry {
namespace {

std::string write_temp(const std::string& text) {
  char name[] = "/tmp/workcell_test_XXXXXX";
  const int fd = mkstemp(name);
  EXPECT_GE(fd, 0);
  std::ofstream(name) << text;
  return name;
}

TEST(WorkcellFile, UnsetFieldsKeepTheShepherdingDefaults) {
  const Workcell cell = load_workcell_file(write_temp("tool_length_mm: 150 base_yaw_deg: 90\n"));
  EXPECT_DOUBLE_EQ(cell.tool_length_mm, 150.0);
  EXPECT_NEAR(cell.base_yaw_rad, M_PI / 2.0, 1e-12);
  EXPECT_DOUBLE_EQ(cell.field_length_mm, Workcell{}.field_length_mm);
}

TEST(WorkcellFile, BadValuesAreRefusedNamingTheField) {
  try {
    load_workcell_file(write_temp("field_length_mm: 100\ntool_length_mm: -5\n"));
    FAIL() << "a negative tool length was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("tool_length_mm"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(":2"), std::string::npos) << "line missing: " << e.what();
  }
  EXPECT_THROW(load_workcell_file(write_temp("tool_length: 5\n")), ConfigError);  // unknown field
  EXPECT_THROW(load_workcell_file("/nonexistent/workcell.pbtxt"), ConfigError);
  EXPECT_THROW(load_workcell_file(write_temp("base_z_mm: nan\n")), ConfigError);
}

TEST(WorkcellFile, TheCatchingCellLoads) {
  const Workcell cell = load_workcell_file((repo_dir() / "deploy/catch/workcell.pbtxt").string());
  EXPECT_GT(cell.tool_length_mm, 0.0);
}

}  // namespace
}  // namespace ephor::geometry
