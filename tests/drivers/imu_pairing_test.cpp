// ImuPairer: accelerometer and gyroscope streams of separate devices into one.
#include "drivers/imu/imu_pairing.h"

#include <gtest/gtest.h>

namespace hs {
namespace {

constexpr int64_t kMs = 1'000'000;

ImuSample accel(int64_t t_ns, double x) {
  return {t_ns, Eigen::Vector3d::Zero(), Eigen::Vector3d(x, 0, 9.81)};
}

ImuSample gyro(int64_t t_ns, double z) {
  return {t_ns, Eigen::Vector3d(0, 0, z), Eigen::Vector3d::Zero()};
}

TEST(ImuPairer, GyroTimesWithTheAccelerationInterpolated) {
  ImuPairer p(20 * kMs, 500 * kMs);
  // Accelerometer at 100 Hz from 10 ms, gyroscope at 400 Hz from 0 (started first).
  std::vector<ImuSample> a, g;
  for (int i = 1; i <= 5; ++i) a.push_back(accel(10 * kMs * i, i));
  for (int i = 0; i <= 24; ++i) g.push_back(gyro(2500'000 * i, 0.1 * i));
  p.add_gyro(g);
  std::vector<ImuSample> out;
  p.take(&out);
  EXPECT_TRUE(out.empty());  // waits for the accelerometer
  p.add_accel(a);
  p.take(&out);
  // 10 ms ... 50 ms: 17 gyroscope samples; the 4 before the first accelerometer one are dropped
  // as leading; 60 ms waits for the next accelerometer sample.
  ASSERT_EQ(out.size(), 17u);
  EXPECT_EQ(p.counters().leading_gyro, 4);
  EXPECT_EQ(p.counters().unpaired_gyro, 0);
  EXPECT_EQ(out[0].t_ns, 10 * kMs);
  EXPECT_DOUBLE_EQ(out[0].accel.x(), 1.0);
  EXPECT_EQ(out[1].t_ns, 12500'000);
  EXPECT_DOUBLE_EQ(out[1].accel.x(), 1.25);  // a quarter of the way from 1 to 2
  EXPECT_DOUBLE_EQ(out[1].gyro.z(), 0.5);
  EXPECT_DOUBLE_EQ(out[1].accel.z(), 9.81);
  EXPECT_EQ(out.back().t_ns, 50 * kMs);
  EXPECT_DOUBLE_EQ(out.back().accel.x(), 5.0);
  for (size_t i = 1; i < out.size(); ++i) EXPECT_GT(out[i].t_ns, out[i - 1].t_ns);

  out.clear();
  p.add_accel({accel(60 * kMs, 6)});
  p.take(&out);
  ASSERT_EQ(out.size(), 4u);  // 52.5 ... 60 ms
  EXPECT_DOUBLE_EQ(out[1].accel.x(), 5.5);
  EXPECT_EQ(p.counters().paired, 21);
}

TEST(ImuPairer, AnAccelerometerGapDropsTheGyroSamplesInIt) {
  ImuPairer p(20 * kMs, 500 * kMs);
  p.add_accel({accel(0, 0), accel(10 * kMs, 1), accel(50 * kMs, 5), accel(60 * kMs, 6)});
  std::vector<ImuSample> g;
  for (int i = 0; i <= 12; ++i) g.push_back(gyro(5 * kMs * i, 0));
  p.add_gyro(g);
  std::vector<ImuSample> out;
  p.take(&out);
  // 15 ... 45 ms lie in the 40 ms gap: 7 dropped, said why.
  EXPECT_EQ(out.size(), 6u);
  EXPECT_EQ(p.counters().unpaired_gyro, 7);
  EXPECT_NE(p.last_error().find("40 ms gap of the accelerometer"), std::string::npos)
      << p.last_error();
}

TEST(ImuPairer, GyroSamplesDoNotWaitForASilentAccelerometerForever) {
  ImuPairer p(20 * kMs, 100 * kMs);
  std::vector<ImuSample> g;
  for (int i = 0; i < 50; ++i) g.push_back(gyro(5 * kMs * i, 0));
  p.add_gyro(g);
  std::vector<ImuSample> out;
  p.take(&out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(p.counters().unpaired_gyro, 29);  // those more than 100 ms behind the newest
  EXPECT_NE(p.last_error().find("no accelerometer samples for"), std::string::npos);

  // The accelerometer stops after 0 ms: a sample within the gap after it waits for the next
  // one, until the gyroscope has run the wait ahead; then it and those behind go.
  ImuPairer q(20 * kMs, 100 * kMs);
  q.add_accel({accel(0, 0)});
  q.add_gyro({gyro(0, 0), gyro(10 * kMs, 0), gyro(30 * kMs, 0)});
  q.take(&out);
  EXPECT_EQ(out.size(), 1u);  // the one at 0; 10 ms waits
  EXPECT_EQ(q.counters().unpaired_gyro, 0);
  q.add_gyro({gyro(115 * kMs, 0)});
  q.take(&out);
  EXPECT_EQ(out.size(), 1u);
  // 10 ms waited too long; 30 and 115 ms are past the gap, whatever comes next.
  EXPECT_EQ(q.counters().unpaired_gyro, 3);
  EXPECT_NE(q.last_error().find("within 20 ms after it"), std::string::npos) << q.last_error();
  q.restart();
  q.add_accel({accel(100 * kMs, 0)});
  q.add_gyro({gyro(100 * kMs, 0)});
  q.take(&out);
  EXPECT_EQ(out.size(), 2u);  // nothing of before the restart is left waiting
}

}  // namespace
}  // namespace hs
