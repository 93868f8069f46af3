#include "drivers/imu/xsens_stream.h"

#include <gtest/gtest.h>

namespace hs {
namespace {

std::vector<uint8_t> bytes_of(uint16_t counter, uint32_t time) {
  XsensSample s;
  s.packet_counter = counter;
  s.sample_time_fine = time;
  s.accel = Eigen::Vector3d(0, 0, 9.75);
  return encode_xsens_mtdata2(s);
}

std::vector<ImuSample> feed(XsensStream& stream, uint16_t counter, uint32_t time, int64_t rx) {
  const std::vector<uint8_t> b = bytes_of(counter, time);
  return stream.feed(b.data(), b.size(), rx);
}

TEST(XsensStream, SamplesOnTheHostClockAtTheDeviceSpacing) {
  XsensStream stream(DeviceClockOptions{});
  std::vector<ImuSample> all;
  for (int i = 0; i < 10; ++i) {
    const auto s = feed(stream, static_cast<uint16_t>(i), 50u * i, 1'000'000'000 + 5'000'000 * i);
    all.insert(all.end(), s.begin(), s.end());
  }
  ASSERT_EQ(all.size(), 10u);
  for (size_t i = 1; i < all.size(); ++i) EXPECT_EQ(all[i].t_ns - all[i - 1].t_ns, 5'000'000);
  EXPECT_EQ(all[0].accel.z(), 9.75);
  EXPECT_EQ(stream.counters().lost_samples, 0);
}

TEST(XsensStream, CounterGapsAreLostSamplesAndRepeatedTimesAreDropped) {
  XsensStream stream(DeviceClockOptions{});
  EXPECT_EQ(feed(stream, 65534, 100, 1'000'000).size(), 1u);
  EXPECT_EQ(feed(stream, 65535, 150, 6'000'000).size(), 1u);
  EXPECT_EQ(feed(stream, 2, 300, 21'000'000).size(), 1u);  // 0 and 1 lost (across the wrap)
  EXPECT_EQ(stream.counters().lost_samples, 2);
  EXPECT_TRUE(feed(stream, 3, 300, 26'000'000).empty());  // same device time
  EXPECT_TRUE(feed(stream, 4, 250, 31'000'000).empty());  // back in time
  EXPECT_EQ(stream.counters().backwards, 2);
  EXPECT_NE(stream.last_error().find("went back or repeated"), std::string::npos);
}

TEST(XsensStream, AResetStartsTheDeviceAnewAndKeepsTheCounts) {
  XsensStream stream(DeviceClockOptions{});
  std::vector<uint8_t> bad = bytes_of(1, 50);
  bad[10] ^= 1;
  stream.feed(bad.data(), bad.size(), 1'000'000);
  EXPECT_EQ(feed(stream, 7, 5000, 2'000'000).size(), 1u);
  stream.reset();  // reconnected: the device restarted its counters
  EXPECT_EQ(feed(stream, 0, 10, 3'000'000).size(), 1u) << "not 'back in time' after a reset";
  EXPECT_EQ(stream.protocol().bad_checksum, 1);
  EXPECT_EQ(stream.protocol().samples, 2);
  EXPECT_EQ(stream.counters().clock_restarts, 1);
  EXPECT_EQ(stream.counters().backwards, 0);
}

}  // namespace
}  // namespace hs
