#include "common/config/manifest.h"

#include <gtest/gtest.h>

#include "common/config/text_proto.h"

namespace ephor {
namespace {

constexpr const char* kGood = R"pb(
  name: "small"
  lcm { port: 7700 }
  host { name: "planning" }
  host { name: "arm" }
  process {
    name: "vision"
    host: "planning"
    exec: "ephor-testtask"
    task { name: "blobify" kind: PERIODIC period_ms: 50 cpu: "1" }
  }
  process {
    name: "arm"
    host: "arm"
    exec: "ephor-testtask"
    task { name: "move" kind: TRIGGERED deadline_ms: 200 }
  }
)pb";

// Parses `text` and returns the ConfigError message ("" when it loads).
std::string error_of(const std::string& text) {
  try {
    parse_manifest(text, "bad.pbtxt");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Manifest, GoodFileLoadsWithDefaults) {
  const auto m = parse_manifest(kGood, "good.pbtxt");
  EXPECT_EQ(m.name(), "small");
  EXPECT_EQ(manifest_lcm_url(m), "udpm://239.255.76.67:7700?ttl=0&recv_buf_size=16777216");
  ASSERT_EQ(m.process_size(), 2);
  const auto& blobify = m.process(0).task(0);
  EXPECT_EQ(blobify.deadline_ms(), 50.0);  // defaults to the period
  EXPECT_EQ(blobify.policy(), config::Task::FIFO);
  EXPECT_EQ(task_cpu(blobify), 1);
  EXPECT_EQ(task_cpu(m.process(1).task(0)), -1);  // "auto"
  EXPECT_EQ(m.scheduler().estimate_window(), 3u);
  EXPECT_TRUE(m.scheduler().migrate());
  EXPECT_EQ(m.scheduler().cpu_latency_us(), 0);  // idle CPUs poll while the scheduler runs
}

TEST(Manifest, CpuLatencyRequestIsMinusOneOrAnAmountOfMicroseconds) {
  EXPECT_EQ(parse_manifest("name: \"x\" scheduler { cpu_latency_us: -1 }", "x")
                .scheduler()
                .cpu_latency_us(),
            -1);
  const std::string err = error_of("name: \"x\"\nscheduler { cpu_latency_us: -5 }\n");
  EXPECT_NE(err.find("scheduler.cpu_latency_us"), std::string::npos) << err;
}

TEST(Manifest, ReceiveBufferIsRaisedNeverLowered) {
  EXPECT_EQ(lcm_url_with_receive_buffer("udpm://239.255.76.67:7667?ttl=0&recv_buf_size=16777216",
                                        33554432),
            "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=33554432");
  EXPECT_EQ(lcm_url_with_receive_buffer("udpm://239.255.76.67:7667?recv_buf_size=100&ttl=1", 200),
            "udpm://239.255.76.67:7667?recv_buf_size=200&ttl=1");
  EXPECT_EQ(lcm_url_with_receive_buffer("udpm://239.255.76.67:7667?recv_buf_size=500", 200),
            "udpm://239.255.76.67:7667?recv_buf_size=500");
  EXPECT_EQ(lcm_url_with_receive_buffer("udpm://239.255.76.67:7667", 200),
            "udpm://239.255.76.67:7667?recv_buf_size=200");
  EXPECT_EQ(lcm_url_with_receive_buffer("udpm://239.255.76.67:7667?ttl=0", 200),
            "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=200");
}

// A check about a whole repeated field ("process", no index) names the file
// and the field, as a ConfigError, not protobuf's own index complaint.
TEST(TextProtoTest, ARepeatedFieldNamedWithoutAnIndexIsAConfigError) {
  config::Manifest m;
  const auto src =
      TextProto::from_string("name: \"x\"\nprocess { name: \"a\" exec: \"b\" }\n", "x.pbtxt", &m);
  try {
    src->fail("process", "needs two");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), "x.pbtxt: process: needs two");
  }
  try {
    src->fail("name[3]", "an index on a single field is ignored");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("x.pbtxt:1: name[3]"), std::string::npos) << e.what();
  }
}

TEST(Manifest, NoHostsMeansOneLocalHost) {
  const auto m = parse_manifest(R"pb(name: "x"
                                     process { name: "a" exec: "b" })pb",
                                "x");
  ASSERT_EQ(manifest_hosts(m), std::vector<std::string>{"local"});
  EXPECT_EQ(m.process(0).host(), "local");
}

TEST(Manifest, SyntaxErrorNamesFileLineAndColumn) {
  const std::string err = error_of("name: \"x\"\nprocess {\n  name: \"a\"\n  exec \"b\"\n}\n");
  EXPECT_NE(err.find("bad.pbtxt:4:"), std::string::npos) << err;
}

TEST(Manifest, UnknownFieldIsNamed) {
  const std::string err =
      error_of("name: \"x\"\nprocess { name: \"a\" exec: \"b\" perod_ms: 3 }\n");
  EXPECT_NE(err.find("bad.pbtxt:2:"), std::string::npos) << err;
  EXPECT_NE(err.find("perod_ms"), std::string::npos) << err;
}

TEST(Manifest, SemanticErrorNamesLineAndFieldPath) {
  const std::string err = error_of(
      "name: \"x\"\n"
      "process {\n"
      "  name: \"a\"\n"
      "  exec: \"b\"\n"
      "  task { name: \"t\" kind: PERIODIC period_ms: 0 }\n"
      "}\n");
  EXPECT_NE(err.find("bad.pbtxt:5: process[0].task[0].period_ms"), std::string::npos) << err;
}

TEST(Manifest, RejectsBadValues) {
  EXPECT_NE(error_of(R"pb(name: "x"
                          process {
                            name: "a"
                            exec: "b"
                            task { name: "t" kind: PERIODIC period_ms: nan }
                          })pb"),
            "");
  EXPECT_NE(error_of(R"pb(name: "x"
                          process {
                            name: "a"
                            exec: "b"
                            task { name: "t" kind: PERIODIC period_ms: 1 cpu: "two" }
                          })pb"),
            "");
  EXPECT_NE(error_of(R"pb(name: "x"
                          process {
                            name: "a"
                            exec: "b"
                            task { name: "t" kind: TRIGGERED }
                          })pb"),
            "");
  EXPECT_NE(error_of(R"pb(name: "x"
                          process {
                            name: "a"
                            exec: "b"
                            task { name: "t" kind: PERIODIC period_ms: 1 priority: 120 }
                          })pb"),
            "");
  EXPECT_NE(error_of(R"pb(name: "x"
                          process { name: "a" exec: "b" host: "nowhere" })pb"),
            "");
  EXPECT_NE(error_of(R"pb(name: "x"
                          process { name: "a" exec: "b" }
                          process { name: "a" exec: "c" })pb"),
            "");
  EXPECT_NE(error_of(R"pb(name: "x"
                          lcm { ttl: 4 })pb"),
            "");
  EXPECT_NE(error_of(R"pb(process { name: "a" exec: "b" })pb"), "");
}

TEST(Manifest, ParametersExpandInArgsAndEmptyOnesDropTheArg) {
  const auto m = parse_manifest(
      R"pb(
        name: "x"
        param { name: "seed" default_value: "1" }
        param { name: "summary" }
        process {
          name: "a"
          exec: "b"
          args: [ "--seed=${seed}", "--summary=${summary}", "plain", "${seed}x${seed}" ]
        }
      )pb",
      "x");
  EXPECT_EQ(expand_args(m.process(0), {{"seed", "7"}, {"summary", ""}}),
            (std::vector<std::string>{"--seed=7", "plain", "7x7"}));
  EXPECT_NE(error_of(R"pb(name: "x"
                          process {
                            name: "a"
                            exec: "b"
                            args: [ "--n=${nope}" ]
                          })pb"),
            "");
  EXPECT_NE(error_of(R"pb(name: "x"
                          param { name: "Bad Name" })pb"),
            "");
}

TEST(Manifest, MissingFileIsNamed) {
  try {
    load_manifest("/nonexistent/m.pbtxt");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/m.pbtxt"), std::string::npos);
  }
}

// A folder opens as an empty stream: it must not load as an empty manifest.
TEST(Manifest, FolderIsRefused) {
  try {
    load_manifest("/tmp");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/tmp: is a folder"), std::string::npos);
  }
}

}  // namespace
}  // namespace ephor
