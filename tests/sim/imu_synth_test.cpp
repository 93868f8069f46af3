// The synthetic IMU is the exact derivative of the trajectory (integrating it reproduces the
// ground truth), and its noise has the configured densities.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "common/sim/imu_synth.h"
#include "scenario_test_util.h"

namespace hs::sim {
namespace {

const Eigen::Vector3d kGravityW(0, 0, -kGravityMps2);

struct State {
  Eigen::Quaterniond q;
  Eigen::Vector3d v, p;
};

struct Rate {
  Eigen::Vector4d dq;  // quaternion coefficients (x, y, z, w)
  Eigen::Vector3d dv, dp;
};

Rate rate_of(const State& s, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel) {
  const Eigen::Quaterniond omega(0, gyro.x(), gyro.y(), gyro.z());
  return {0.5 * (s.q * omega).coeffs(), s.q * accel + kGravityW, s.v};
}

State step(const State& s, const Rate& r, double dt) {
  State out;
  out.q.coeffs() = s.q.coeffs() + dt * r.dq;
  out.v = s.v + dt * r.dv;
  out.p = s.p + dt * r.dp;
  return out;
}

// Cubic (Catmull-Rom) interpolation between samples b and c at fraction f.
Eigen::Vector3d cubic(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                      const Eigen::Vector3d& d, double f) {
  return b +
         0.5 * f * (c - a + f * (2.0 * a - 5.0 * b + 4.0 * c - d + f * (3.0 * (b - c) + d - a)));
}

TEST(ImuSynthTest, NoiseFreeIntegrationReproducesGroundTruth) {
  Scenario sc = testing::test_scenario("room_mav");
  ImuSynthOptions opt = sc.imu;
  opt.gyro_noise_density = opt.accel_noise_density = 0.0;
  opt.gyro_random_walk = opt.accel_random_walk = 0.0;  // constant (known) biases stay in
  const Trajectory trajectory(sc.trajectory);
  const int64_t t0 = 0;
  const ImuSeries imu = synthesize_imu(trajectory, opt, t0, s_to_ns(sc.duration_s), 11);
  ASSERT_EQ(imu.samples.size(), imu.truth.size());

  // Integrate 10 s of the busiest part of the flight with RK4 on the interpolated samples.
  const size_t first = 800, count = 2000;  // from 4 s (moving), 200 Hz
  ASSERT_LT(first + count + 2, imu.samples.size());
  const NavState& start = imu.truth[first];
  State s{start.q_w_b, start.v_w, start.p_w_b};
  const auto gyro = [&](size_t k) { return imu.samples[k].gyro - opt.gyro_bias; };
  const auto accel = [&](size_t k) { return imu.samples[k].accel - opt.accel_bias; };
  for (size_t k = first; k < first + count; ++k) {
    const double dt = ns_to_s(imu.samples[k + 1].t_ns - imu.samples[k].t_ns);
    const Eigen::Vector3d g_mid = cubic(gyro(k - 1), gyro(k), gyro(k + 1), gyro(k + 2), 0.5);
    const Eigen::Vector3d a_mid = cubic(accel(k - 1), accel(k), accel(k + 1), accel(k + 2), 0.5);
    const Rate k1 = rate_of(s, gyro(k), accel(k));
    const Rate k2 = rate_of(step(s, k1, dt / 2), g_mid, a_mid);
    const Rate k3 = rate_of(step(s, k2, dt / 2), g_mid, a_mid);
    const Rate k4 = rate_of(step(s, k3, dt), gyro(k + 1), accel(k + 1));
    const Rate sum{k1.dq + 2 * k2.dq + 2 * k3.dq + k4.dq, k1.dv + 2 * k2.dv + 2 * k3.dv + k4.dv,
                   k1.dp + 2 * k2.dp + 2 * k3.dp + k4.dp};
    s = step(s, sum, dt / 6);
    s.q.normalize();
  }
  const NavState& end = imu.truth[first + count];
  const double travelled = (end.p_w_b - start.p_w_b).norm();
  EXPECT_GT(travelled, 2.0) << "the segment should move";
  EXPECT_LT((s.p - end.p_w_b).norm(), 1e-3);
  EXPECT_LT(s.q.angularDistance(end.q_w_b) * 180.0 / M_PI, 0.01);
  EXPECT_LT((s.v - end.v_w).norm(), 1e-3);
}

double sample_std(const std::vector<double>& x) {
  const double mean = std::accumulate(x.begin(), x.end(), 0.0) / static_cast<double>(x.size());
  double ss = 0;
  for (const double v : x) ss += (v - mean) * (v - mean);
  return std::sqrt(ss / static_cast<double>(x.size() - 1));
}

TEST(ImuSynthTest, NoiseMatchesConfiguredDensities) {
  const Scenario sc = testing::test_scenario("static");
  const Trajectory trajectory(sc.trajectory);
  const ImuSeries imu = synthesize_imu(trajectory, sc.imu, 0, s_to_ns(30.0), 5);
  const double dt = 1.0 / sc.imu.rate_hz;
  std::vector<double> gyro_white, accel_white, gyro_steps, accel_steps;
  for (size_t k = 0; k < imu.samples.size(); ++k) {
    const ImuSample ideal = ideal_imu(trajectory.at(ns_to_s(imu.samples[k].t_ns)), 0);
    const NavState& truth = imu.truth[k];
    for (int i = 0; i < 3; ++i) {
      gyro_white.push_back(imu.samples[k].gyro[i] - ideal.gyro[i] - truth.gyro_bias[i]);
      accel_white.push_back(imu.samples[k].accel[i] - ideal.accel[i] - truth.accel_bias[i]);
      if (k == 0) continue;
      gyro_steps.push_back(truth.gyro_bias[i] - imu.truth[k - 1].gyro_bias[i]);
      accel_steps.push_back(truth.accel_bias[i] - imu.truth[k - 1].accel_bias[i]);
    }
  }
  const auto expect_within_10pct = [](double measured, double expected, const char* what) {
    EXPECT_NEAR(measured / expected, 1.0, 0.1) << what << ": " << measured << " vs " << expected;
  };
  expect_within_10pct(sample_std(gyro_white), sc.imu.gyro_noise_density / std::sqrt(dt), "gyro");
  expect_within_10pct(sample_std(accel_white), sc.imu.accel_noise_density / std::sqrt(dt), "acc");
  expect_within_10pct(sample_std(gyro_steps), sc.imu.gyro_random_walk * std::sqrt(dt), "bg walk");
  expect_within_10pct(sample_std(accel_steps), sc.imu.accel_random_walk * std::sqrt(dt), "ba walk");
  EXPECT_EQ(imu.truth.front().gyro_bias, sc.imu.gyro_bias);
  EXPECT_EQ(imu.truth.front().accel_bias, sc.imu.accel_bias);
}

TEST(ImuSynthTest, BiasWalkSpreadsLikeBrownianMotionAcrossSeeds) {
  // Variance of the bias after T seconds over many runs: random_walk^2 * T.
  const Scenario sc = testing::test_scenario("static");
  const Trajectory trajectory(sc.trajectory);
  const double T = 2.0;
  std::vector<double> gyro_end, accel_end;
  for (uint64_t seed = 0; seed < 400; ++seed) {
    const ImuSeries imu = synthesize_imu(trajectory, sc.imu, 0, s_to_ns(T), seed);
    const NavState& last = imu.truth.back();
    for (int i = 0; i < 3; ++i) {
      gyro_end.push_back(last.gyro_bias[i] - sc.imu.gyro_bias[i]);
      accel_end.push_back(last.accel_bias[i] - sc.imu.accel_bias[i]);
    }
  }
  EXPECT_NEAR(sample_std(gyro_end) / (sc.imu.gyro_random_walk * std::sqrt(T)), 1.0, 0.1);
  EXPECT_NEAR(sample_std(accel_end) / (sc.imu.accel_random_walk * std::sqrt(T)), 1.0, 0.1);
}

TEST(ImuSynthTest, GapLeavesExactlyTheConfiguredHole) {
  const Scenario sc = testing::test_scenario("imu_gap");
  ASSERT_EQ(sc.events.imu_gaps.size(), 1u);
  ImuSynthOptions opt = sc.imu;
  opt.gaps = sc.events.imu_gaps;
  const Trajectory trajectory(sc.trajectory);
  const int64_t t0 = sc.start_time_ns;
  const ImuSeries imu = synthesize_imu(trajectory, opt, t0, t0 + s_to_ns(sc.duration_s), 3);
  const int64_t period = imu_period_ns(opt.rate_hz);
  int holes = 0;
  for (size_t k = 1; k < imu.samples.size(); ++k) {
    const int64_t dt = imu.samples[k].t_ns - imu.samples[k - 1].t_ns;
    if (dt == period) continue;
    ++holes;
    EXPECT_EQ(dt, s_to_ns(0.5));
    EXPECT_EQ(imu.samples[k - 1].t_ns - t0, s_to_ns(15.0));
  }
  EXPECT_EQ(holes, 1);
  EXPECT_EQ(imu.truth.size(), imu.samples.size() + 99);  // ground truth keeps its 200 Hz
}

}  // namespace
}  // namespace hs::sim
