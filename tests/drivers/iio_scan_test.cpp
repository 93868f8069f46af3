#include "drivers/imu/iio_scan.h"

#include <gtest/gtest.h>

#include "common/core/error.h"

namespace hs {
namespace {

TEST(IioScanType, ParsesTheKernelsFormat) {
  const IioScanType a = parse_iio_scan_type("le:s16/16>>0\n");
  EXPECT_FALSE(a.big_endian);
  EXPECT_TRUE(a.is_signed);
  EXPECT_EQ(a.realbits, 16);
  EXPECT_EQ(a.storagebits, 16);
  EXPECT_EQ(a.shift, 0);
  const IioScanType b = parse_iio_scan_type("be:u12/16>>4");
  EXPECT_TRUE(b.big_endian);
  EXPECT_FALSE(b.is_signed);
  EXPECT_EQ(b.realbits, 12);
  EXPECT_EQ(b.shift, 4);
  const IioScanType c = parse_iio_scan_type("le:s20/32X3>>0");
  EXPECT_EQ(c.repeat, 3);
  EXPECT_EQ(c.bytes(), 12u);
}

TEST(IioScanType, RejectsWhatItCannotDecode) {
  for (const char* bad : {"", "le:s16", "xe:s16/16>>0", "le:q16/16>>0", "le:s16/12>>0",
                          "le:s16/16>>4", "le:s0/16>>0", "le:s16/16>>0 junk"}) {
    EXPECT_THROW(parse_iio_scan_type(bad), InputError) << bad;
  }
}

std::vector<IioScanChannel> channels(std::initializer_list<std::pair<int, const char*>> list) {
  std::vector<IioScanChannel> out;
  for (const auto& [index, type] : list) {
    IioScanChannel c;
    c.name = "ch" + std::to_string(index);
    c.index = index;
    c.type = parse_iio_scan_type(type);
    out.push_back(c);
  }
  return out;
}

TEST(IioScanLayout, AlignsEachChannelToItsSizeInIndexOrder) {
  // Three 16-bit axes then the 64-bit timestamp: 6 bytes, padded to 8 before it.
  auto imu = channels(
      {{3, "le:s64/64>>0"}, {0, "le:s16/16>>0"}, {2, "le:s16/16>>0"}, {1, "le:s16/16>>0"}});
  EXPECT_EQ(layout_iio_scan(imu), 16u);
  EXPECT_EQ(imu[0].index, 0);
  EXPECT_EQ(imu[1].offset, 2u);
  EXPECT_EQ(imu[2].offset, 4u);
  EXPECT_EQ(imu[3].offset, 8u);
  // A byte then a 32-bit value: 3 bytes of padding; the scan padded to the largest (4).
  auto mixed = channels({{0, "le:u8/8>>0"}, {1, "le:s32/32>>0"}, {2, "le:u8/8>>0"}});
  EXPECT_EQ(layout_iio_scan(mixed), 12u);
  EXPECT_EQ(mixed[1].offset, 4u);
  EXPECT_EQ(mixed[2].offset, 8u);
}

TEST(IioScanDecode, EndianShiftMaskAndSign) {
  auto c = channels({{0, "be:s12/16>>4"}, {1, "le:u13/16>>0"}, {2, "le:s64/64>>0"}});
  layout_iio_scan(c);
  // -5 in 12 bits, shifted left by 4, big endian, with junk in the low nibble.
  const uint16_t be = static_cast<uint16_t>((0xFFB << 4) | 0x7);
  // 13 bits unsigned with junk above them.
  const uint16_t le = 0xE000 | 4000;
  const int64_t t = -1234567890123;
  uint8_t scan[16] = {};
  scan[0] = static_cast<uint8_t>(be >> 8);
  scan[1] = static_cast<uint8_t>(be & 0xFF);
  scan[2] = static_cast<uint8_t>(le & 0xFF);
  scan[3] = static_cast<uint8_t>(le >> 8);
  for (int i = 0; i < 8; ++i)
    scan[8 + i] = static_cast<uint8_t>(static_cast<uint64_t>(t) >> (8 * i));
  EXPECT_EQ(decode_iio_value(scan, c[0]), -5);
  EXPECT_EQ(decode_iio_value(scan, c[1]), 4000);
  EXPECT_EQ(decode_iio_value(scan, c[2]), t);
}

}  // namespace
}  // namespace hs
