// Prints the cost of IMU preintegration per integrated sample (not a test: timings vary).
#include <chrono>
#include <cstdio>

#include "common/imu/imu_residual.h"
#include "tests/imu/analytic_motion.h"

int main() {
  using Clock = std::chrono::steady_clock;
  const hs::test::AnalyticMotion motion;
  const int64_t period = 5'000'000;  // 200 Hz
  const int64_t total = hs::s_to_ns(60.0);
  const auto samples = motion.samples(0, total, period);

  // Camera-rate windows (20 Hz, 10 samples each), as the tracker uses them.
  const int64_t window = 50'000'000;
  double checksum = 0.0;
  const auto start = Clock::now();
  for (int64_t t = 0; t + window <= total; t += window) {
    const hs::ImuPreintegration pim = hs::preintegrate(samples, t, t + window, hs::ImuBias{});
    checksum += pim.delta().p.x();
  }
  const double ns_windows = std::chrono::duration<double, std::nano>(Clock::now() - start).count();

  // One long window: the per-step cost without the search for the window start.
  const auto start_long = Clock::now();
  const hs::ImuPreintegration pim = hs::preintegrate(samples, 0, total, hs::ImuBias{});
  const double ns_long =
      std::chrono::duration<double, std::nano>(Clock::now() - start_long).count();

  // Residual with Jacobians.
  const hs::NavState s_i = motion.state(0), s_j = motion.state(total);
  hs::ImuResidualJacobians J;
  const int reps = 100000;
  const auto start_res = Clock::now();
  for (int k = 0; k < reps; ++k) {
    checksum += hs::imu_residual(pim, s_i.q_w_b.toRotationMatrix(), s_i.p_w_b, s_i.v_w,
                                 s_j.q_w_b.toRotationMatrix(), s_j.p_w_b, s_j.v_w, hs::ImuBias{},
                                 hs::default_gravity_w(), &J)[0];
  }
  const double ns_res = std::chrono::duration<double, std::nano>(Clock::now() - start_res).count();

  const double n = static_cast<double>(total / period);
  std::printf("preintegration, 50 ms windows over a 60 s buffer: %.0f ns per sample\n",
              ns_windows / n);
  std::printf("preintegration, one 60 s window: %.0f ns per sample\n", ns_long / n);
  std::printf("residual + Jacobians: %.0f ns per call\n", ns_res / reps);
  std::printf("(checksum %.3g)\n", checksum);
  return 0;
}
