#include <gtest/gtest.h>

#include <iostream>
#include <random>

#include "common/imu/preintegration.h"
#include "common/imu/so3.h"
#include "tests/imu/analytic_motion.h"

namespace hs {
namespace {

// Monte Carlo: white noise of the continuous densities, discretised at the sample rate, added
// to exact samples. The spread of the deltas around the noiseless ones must match the
// propagated covariance.
TEST(PreintegrationCovariance, MatchesMonteCarlo) {
  const test::AnalyticMotion motion;
  const ImuOptions options;  // EuRoC noise, 200 Hz
  const int64_t period = s_to_ns(1.0 / options.noise.rate_hz);
  const int64_t t0 = 0, t1 = s_to_ns(1.0);
  const auto exact = motion.samples(t0, t1, period);
  const ImuPreintegration nominal = preintegrate(exact, t0, t1, ImuBias{}, options);
  const Matrix9d& P = nominal.covariance();
  ASSERT_TRUE(P.allFinite());
  const Eigen::LLT<Matrix9d> P_llt(P);
  ASSERT_EQ(P_llt.info(), Eigen::Success);

  std::mt19937_64 rng(12345);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double sigma_g = options.noise.gyro_noise_density * std::sqrt(options.noise.rate_hz);
  const double sigma_a = options.noise.accel_noise_density * std::sqrt(options.noise.rate_hz);
  const int runs = 600;
  Matrix9d S = Matrix9d::Zero();
  double nees_sum = 0.0;
  for (int run = 0; run < runs; ++run) {
    std::vector<ImuSample> noisy = exact;
    for (ImuSample& s : noisy) {
      for (int k = 0; k < 3; ++k) {
        s.gyro[k] += sigma_g * gauss(rng);
        s.accel[k] += sigma_a * gauss(rng);
      }
    }
    const ImuDelta d = preintegrate(noisy, t0, t1, ImuBias{}, options).delta();
    Vector9d e;
    e << so3::log(nominal.delta().R.transpose() * d.R), d.v - nominal.delta().v,
        d.p - nominal.delta().p;
    S += e * e.transpose();
    nees_sum += e.dot(P_llt.solve(e));
  }
  S /= runs;

  std::cout << "NEES " << nees_sum / runs << ", block variance ratios "
            << S.block<3, 3>(0, 0).trace() / P.block<3, 3>(0, 0).trace() << " "
            << S.block<3, 3>(3, 3).trace() / P.block<3, 3>(3, 3).trace() << " "
            << S.block<3, 3>(6, 6).trace() / P.block<3, 3>(6, 6).trace() << "\n";
  // Normalised estimation error squared: chi^2 with 9 dof on average, std 0.17 over 600 runs.
  EXPECT_NEAR(nees_sum / runs, 9.0, 0.9);
  // Each block's total variance within 12% (sampling std ~3-6%).
  for (int b = 0; b < 3; ++b) {
    const double predicted = P.block<3, 3>(3 * b, 3 * b).trace();
    const double measured = S.block<3, 3>(3 * b, 3 * b).trace();
    EXPECT_NEAR(measured / predicted, 1.0, 0.12) << "block " << b;
  }
  // The rotation-position correlation is strong at this motion; check its sign and size.
  const double c_pred = P(0, 6) / std::sqrt(P(0, 0) * P(6, 6));
  const double c_meas = S(0, 6) / std::sqrt(S(0, 0) * S(6, 6));
  EXPECT_NEAR(c_meas, c_pred, 0.15);
}

TEST(PreintegrationCovariance, GrowsWithWindowAndNoise) {
  const test::AnalyticMotion motion;
  const auto samples = motion.samples(0, s_to_ns(2.0), 5'000'000);
  ImuOptions quiet;
  ImuOptions loud;
  loud.noise.gyro_noise_density *= 2.0;
  loud.noise.accel_noise_density *= 2.0;
  const Matrix9d P1 = preintegrate(samples, 0, s_to_ns(1.0), ImuBias{}, quiet).covariance();
  const Matrix9d P2 = preintegrate(samples, 0, s_to_ns(2.0), ImuBias{}, quiet).covariance();
  const Matrix9d P_loud = preintegrate(samples, 0, s_to_ns(1.0), ImuBias{}, loud).covariance();
  // Gyro white noise: rotation variance ~= 3 sigma^2 T (up to the small per-step rotations).
  const double rot_var = P1.topLeftCorner<3, 3>().trace();
  EXPECT_NEAR(rot_var / (3.0 * 1.6968e-04 * 1.6968e-04 * 1.0), 1.0, 1e-3);
  // Position variance grows at least like T^3 under accelerometer noise.
  const double pos_var1 = P1.bottomRightCorner<3, 3>().trace();
  const double pos_var2 = P2.bottomRightCorner<3, 3>().trace();
  EXPECT_GT(pos_var2, 4.0 * pos_var1);
  EXPECT_NEAR((P_loud - 4.0 * P1).norm() / P1.norm(), 0.0, 1e-12);
  EXPECT_LT((P1 - P1.transpose()).norm(), 1e-15 * P1.norm() + 1e-30);
}

}  // namespace
}  // namespace hs
