#include "tools/log/lcm_schema.h"

#include <cstdlib>

#include <gtest/gtest.h>

#include "tools/log/all_lcm_types.h"
#include "tools/log/repo_schema_for_tests.h"

namespace ephor::logtools {
namespace {

std::string types_dir() { return repo_lcmtypes_dir(); }

// The decoder finds a message's type by its fingerprint: it must equal what
// lcm-gen put into the C++ types, for every one of our types.
TEST(LcmSchema, FingerprintsMatchLcmGenForEveryType) {
  const auto schema = LcmSchema::load_directory(types_dir());
  int checked = 0;
#define EPHOR_CHECK_TYPE(name)                                                                 \
  EXPECT_EQ(schema.fingerprint("ephor." #name), static_cast<uint64_t>(ephor::name::getHash())) \
      << #name;                                                                                \
  ++checked;
  EPHOR_ALL_LCM_TYPES(EPHOR_CHECK_TYPE)
#undef EPHOR_CHECK_TYPE
  EXPECT_EQ(checked, static_cast<int>(schema.names().size()));
  EXPECT_GE(checked, 20);
}

TEST(LcmSchema, FindsTypesByShortAndFullNameAndFingerprint) {
  const auto schema = LcmSchema::load_directory(types_dir());
  const LcmStruct* objects = schema.find("shepherd_objects_t");
  ASSERT_NE(objects, nullptr);
  EXPECT_EQ(objects, schema.find("ephor.shepherd_objects_t"));
  EXPECT_EQ(objects, schema.find_by_fingerprint(
                         static_cast<uint64_t>(ephor::shepherd_objects_t::getHash())));
  EXPECT_EQ(schema.find("no_such_t"), nullptr);
  const auto& m = objects->members;
  ASSERT_GE(m.size(), 5u);
  EXPECT_EQ(m[1].type, "ephor.header_t");
  EXPECT_EQ(m.back().name, "objects");
  ASSERT_EQ(m.back().dimensions.size(), 1u);
  EXPECT_TRUE(m.back().dimensions[0].variable);
  EXPECT_EQ(m.back().dimensions[0].size, "num_objects");
}

TEST(LcmSchema, ParsesConstsFixedArraysAndSeveralMembersPerLine) {
  LcmSchema schema;
  schema.add_text(R"(package p; /* block
  comment */ struct a_t { const int8_t K = 1, L = -2; double q[3][2]; int32_t n, m; // note
  string s[n]; b_t b; } struct b_t { float f; })",
                  "test.lcm");
  schema.resolve();
  const LcmStruct* a = schema.find("p.a_t");
  ASSERT_NE(a, nullptr);
  ASSERT_EQ(a->members.size(), 5u);
  EXPECT_EQ(a->members[0].dimensions.size(), 2u);
  EXPECT_EQ(a->members[0].dimensions[1].fixed_size, 2);
  EXPECT_EQ(a->members[2].name, "m");
  EXPECT_EQ(a->members[4].type, "p.b_t");
}

TEST(LcmSchema, BadDefinitionsAreNamedWithFileAndLine) {
  auto error_of = [](const std::string& text) {
    try {
      LcmSchema s;
      s.add_text(text, "bad.lcm");
      s.resolve();
    } catch (const SchemaError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error_of("package p;\nstruct a_t {\n int32_t x\n}"),
            "bad.lcm:4: expected ';', got '}'");
  EXPECT_NE(error_of("package p; struct a_t { double d[n]; }").find("earlier integer member"),
            std::string::npos);
  EXPECT_NE(error_of("package p; struct a_t { c_t c; }").find("unknown type p.c_t"),
            std::string::npos);
  EXPECT_NE(error_of("package p; enum e_t { A, B }").find("enums are not supported"),
            std::string::npos);
  EXPECT_NE(error_of("package p; struct a_t { int32_t x; ").find("end of file"), std::string::npos);
  EXPECT_THROW(LcmSchema::load_directory("/nonexistent/types"), SchemaError);
}

}  // namespace
}  // namespace ephor::logtools
