// What the fuzz target arm_command found (issue 18): lcm-gen's decoders threw
// std::length_error out of the bus's receive callback, killing the process,
// for one malformed message: a string length of 0 (the header's sender: every
// message has one) or a negative array count; a count of 2^31 - 1 made a
// process allocate gigabytes. cmake/lcm_bound_counts.sed now makes every
// decoder refuse them, as it refuses a short buffer: decode() returns -1.

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ephor/arm_cmd_t.hpp"
#include "ephor/camera_frame_t.hpp"
#include "ephor/deputy_process_order_t.hpp"

// GCC 12 at -O3 sees lcm-gen's decode() inlined here and wrongly thinks its
// msg_hash may be read uninitialised.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

namespace {

template <class T>
std::vector<uint8_t> encoded(const T& m) {
  std::vector<uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  EXPECT_EQ(m.encode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  return bytes;
}

// LCM writes integers big-endian.
void put_be32(std::vector<uint8_t>& bytes, std::size_t at, int32_t value) {
  const auto u = static_cast<uint32_t>(value);
  for (int i = 0; i < 4; ++i) bytes[at + static_cast<std::size_t>(i)] = (u >> (24 - 8 * i)) & 0xff;
}

ephor::arm_cmd_t image_command() {
  ephor::arm_cmd_t m{};
  m.utime = 1;
  m.seq = 1;
  m.u = 256.0f;
  m.v = 241.0f;
  m.num_points = 0;
  return m;
}

TEST(LcmDecodeBounds, AValidCommandStillDecodes) {
  const std::vector<uint8_t> bytes = encoded(image_command());
  ephor::arm_cmd_t back;
  EXPECT_EQ(back.decode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  EXPECT_EQ(back.seq, 1);
}

TEST(LcmDecodeBounds, AnEmptyOrNegativeStringLengthIsRefusedNotThrown) {
  for (const int32_t length : {0, -1, -100000}) {
    std::vector<uint8_t> bytes = encoded(image_command());
    // fingerprint (8), utime (8), then header_t: utime (8), sender's length (4).
    put_be32(bytes, 24, length);
    ephor::arm_cmd_t back;
    int result = 0;
    EXPECT_NO_THROW(result = back.decode(bytes.data(), 0, static_cast<int>(bytes.size())))
        << "sender length " << length;
    EXPECT_LT(result, 0) << "sender length " << length;
  }
}

TEST(LcmDecodeBounds, ANegativePointCountIsRefusedNotThrown) {
  std::vector<uint8_t> bytes = encoded(image_command());
  put_be32(bytes, bytes.size() - 4, -1);  // num_points is the last field written
  ephor::arm_cmd_t back;
  int result = 0;
  EXPECT_NO_THROW(result = back.decode(bytes.data(), 0, static_cast<int>(bytes.size())));
  EXPECT_LT(result, 0);
}

TEST(LcmDecodeBounds, AHugePointCountIsRefusedWithoutAllocating) {
  std::vector<uint8_t> bytes = encoded(image_command());
  put_be32(bytes, bytes.size() - 4, std::numeric_limits<int32_t>::max());
  ephor::arm_cmd_t back;
  EXPECT_LT(back.decode(bytes.data(), 0, static_cast<int>(bytes.size())), 0);
  EXPECT_EQ(back.traj_t_s.capacity(), 0u);  // refused before any resize
}

TEST(LcmDecodeBounds, AnImageLongerThanItsMessageIsRefused) {
  ephor::camera_frame_t f{};
  f.width = 4;
  f.height = 2;
  f.size = 8;
  f.data.assign(8, 7);
  std::vector<uint8_t> bytes = encoded(f);
  put_be32(bytes, bytes.size() - 12, 1 << 30);  // size, just before the 8 data bytes
  ephor::camera_frame_t back;
  EXPECT_LT(back.decode(bytes.data(), 0, static_cast<int>(bytes.size())), 0);
  EXPECT_EQ(back.data.capacity(), 0u);
}

TEST(LcmDecodeBounds, AStringWithANulByteIsRefused) {
  ephor::arm_cmd_t m = image_command();
  m.header.sender = "ab";
  std::vector<uint8_t> bytes = encoded(m);
  // header_t's sender: length 3 at 24, then 'a' 'b' NUL from 28.
  ASSERT_EQ(bytes[28], 'a');
  ephor::arm_cmd_t back;
  EXPECT_EQ(back.decode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  EXPECT_EQ(back.header.sender, "ab");
  bytes[28] = 0;
  EXPECT_LT(back.decode(bytes.data(), 0, static_cast<int>(bytes.size())), 0);
}

TEST(LcmDecodeBounds, AStringArrayElementWithANulByteIsRefused) {
  ephor::deputy_process_order_t m{};
  m.name = "task";
  m.exec = "ephor-task";
  m.num_args = 1;
  m.args = {"--rate=30"};
  std::vector<uint8_t> bytes = encoded(m);
  ephor::deputy_process_order_t back;
  ASSERT_EQ(back.decode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  ASSERT_EQ(back.args.at(0), "--rate=30");
  const std::string arg = "--rate=30";
  const auto at = std::search(bytes.begin(), bytes.end(), arg.begin(), arg.end());
  ASSERT_NE(at, bytes.end());
  *(at + 6) = 0;  // "--rate\0" + "30"
  EXPECT_LT(back.decode(bytes.data(), 0, static_cast<int>(bytes.size())), 0);
}

}  // namespace
