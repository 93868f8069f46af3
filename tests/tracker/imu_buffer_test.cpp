#include "tracker/imu_buffer.h"

#include <gtest/gtest.h>

#include <limits>

namespace hs {
namespace {

ImuSample sample(int64_t t_ns, double gz = 0.0) {
  ImuSample s;
  s.t_ns = t_ns;
  s.gyro.z() = gz;
  s.accel.z() = 9.81;
  return s;
}

TEST(ImuBuffer, RejectsBadSamplesWithReasons) {
  ImuBuffer buf;
  EXPECT_EQ(buf.push(sample(100)), ImuReject::kAccepted);
  EXPECT_EQ(buf.push(sample(100)), ImuReject::kDuplicate);
  EXPECT_EQ(buf.push(sample(50)), ImuReject::kOutOfOrder);
  EXPECT_EQ(buf.push(sample(200, std::numeric_limits<double>::quiet_NaN())), ImuReject::kNonFinite);
  EXPECT_EQ(buf.push(sample(200, 1e3)), ImuReject::kOutOfRange);
  EXPECT_EQ(buf.push(sample(200)), ImuReject::kAccepted);
  const ImuBufferCounters& c = buf.counters();
  EXPECT_EQ(c.accepted, 2);
  EXPECT_EQ(c.duplicate, 1);
  EXPECT_EQ(c.out_of_order, 1);
  EXPECT_EQ(c.non_finite, 1);
  EXPECT_EQ(c.out_of_range, 1);
  EXPECT_EQ(buf.latest_t_ns(), 200);
}

TEST(ImuBuffer, WindowIncludesNeighboursForInterpolation) {
  ImuBuffer buf;
  for (int64_t t = 0; t <= 100; t += 10) buf.push(sample(t));
  const auto w = buf.window(25, 55);
  ASSERT_EQ(w.size(), 5u);  // 20 30 40 50 60
  EXPECT_EQ(w.front().t_ns, 20);
  EXPECT_EQ(w.back().t_ns, 60);
  EXPECT_EQ(buf.window(30, 50).front().t_ns, 20);
}

TEST(ImuBuffer, ForgetsOldHistory) {
  ImuBufferOptions o;
  o.keep_ns = 100;
  ImuBuffer buf(o);
  for (int64_t t = 0; t <= 1000; t += 10) buf.push(sample(t));
  EXPECT_EQ(buf.window(0, 1000).front().t_ns, 900);
}

}  // namespace
}  // namespace hs
