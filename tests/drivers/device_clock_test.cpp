#include "drivers/imu/device_clock.h"

#include <gtest/gtest.h>

#include <random>

namespace hs {
namespace {

constexpr int64_t kMs = 1'000'000;

// A 200 Hz device whose 10 kHz counter starts at `counter0` and runs `ppm` fast; each sample
// arrives after the wire time plus a random delay of 0..3 ms. Returns the worst error of the
// mapped times against the true host times after the first second.
double worst_error_ms(uint64_t counter0, double ppm, int seconds, bool* increasing) {
  DeviceClockOptions o;
  o.device_hz = 10'000;
  o.counter_bits = 32;
  o.window_ns = 10'000 * kMs;
  o.transmission_ns = 500'000;  // 0.5 ms on the wire
  DeviceClock clock(o);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int64_t> delay(0, 3 * kMs);
  const int64_t host0 = 5'000'000 * kMs;
  double worst = 0;
  int64_t last = 0;
  *increasing = true;
  for (int i = 0; i < 200 * seconds; ++i) {
    const int64_t true_host = host0 + i * 5 * kMs;
    // The device counts (1 + ppm) ticks per true tick.
    const uint64_t counter =
        (counter0 + static_cast<uint64_t>(std::llround(50.0 * i * (1 + ppm * 1e-6)))) &
        0xFFFFFFFFull;
    const int64_t t = clock.to_host(counter, true_host + o.transmission_ns + delay(rng));
    if (t <= last) *increasing = false;
    last = t;
    if (i >= 200) worst = std::max(worst, std::abs(static_cast<double>(t - true_host)) / kMs);
  }
  return worst;
}

TEST(DeviceClock, RecoversTheHostTimeWithinTheLeastDelay) {
  bool increasing = false;
  EXPECT_LT(worst_error_ms(123456, 0.0, 20, &increasing), 0.1);
  EXPECT_TRUE(increasing);
}

TEST(DeviceClock, TheCounterWrappingIsNotTimeGoingBack) {
  DeviceClockOptions o;
  DeviceClock probe(o);
  bool increasing = false;
  // Starts 3 s before the 32-bit counter wraps.
  EXPECT_LT(worst_error_ms((uint64_t{1} << 32) - 30'000, 0.0, 10, &increasing), 0.1);
  EXPECT_TRUE(increasing);
}

TEST(DeviceClock, FollowsCrystalDrift) {
  bool increasing = false;
  // 50 ppm over 120 s is 6 ms of drift; the 10 s window keeps the error well below that.
  EXPECT_LT(worst_error_ms(0, 50.0, 120, &increasing), 0.7);
  EXPECT_TRUE(increasing);
}

}  // namespace
}  // namespace hs
