#include "common/runtime/cpu_latency_request.h"

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace ephor {
namespace {

// A regular file stands in for /dev/cpu_dma_latency: what the request writes
// is the binary 32-bit value the PM QoS interface reads.
TEST(CpuLatencyRequestTest, WritesTheValueAsABinary32BitInteger) {
  const std::string path = ::testing::TempDir() + "cpu_latency_request_test.bin";
  { std::ofstream create(path); }
  {
    const CpuLatencyRequest request(7, path);
    ASSERT_TRUE(request.held()) << request.error();
    EXPECT_TRUE(request.error().empty());
  }
  std::ifstream in(path, std::ios::binary);
  int32_t value = -1;
  in.read(reinterpret_cast<char*>(&value), sizeof value);
  ASSERT_TRUE(in.good());
  EXPECT_EQ(value, 7);
  std::remove(path.c_str());
}

TEST(CpuLatencyRequestTest, AFileThatCannotBeOpenedIsNamedAndNothingIsHeld) {
  const CpuLatencyRequest request(0, "/nonexistent/cpu_dma_latency");
  EXPECT_FALSE(request.held());
  EXPECT_NE(request.error().find("/nonexistent/cpu_dma_latency"), std::string::npos)
      << request.error();
}

TEST(CpuLatencyRequestTest, ANegativeRequestIsRefused) {
  const CpuLatencyRequest request(-1, "/dev/null");
  EXPECT_FALSE(request.held());
  EXPECT_NE(request.error().find(">= 0"), std::string::npos) << request.error();
}

}  // namespace
}  // namespace ephor
