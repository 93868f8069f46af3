#include "common/imu/preintegration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "common/imu/imu_residual.h"
#include "common/imu/so3.h"
#include "tests/imu/analytic_motion.h"

namespace hs {
namespace {

using test::AnalyticMotion;

struct StateError {
  double rot, vel, pos;
};

StateError error(const NavState& a, const NavState& b) {
  return {so3::log(a.q_w_b.conjugate() * b.q_w_b).norm(), (a.v_w - b.v_w).norm(),
          (a.p_w_b - b.p_w_b).norm()};
}

// Predicts the exact trajectory over [t0, t1] from samples at `rate_hz` and returns the error.
StateError prediction_error(int64_t t0_ns, int64_t t1_ns, int rate_hz) {
  const AnalyticMotion motion;
  const int64_t period = s_to_ns(1.0 / rate_hz);
  const auto samples = motion.samples(0, t1_ns, period);
  const ImuPreintegration pim = preintegrate(samples, t0_ns, t1_ns, ImuBias{});
  EXPECT_FALSE(pim.status().has_gap());
  EXPECT_EQ(pim.status().extrapolated_ns, 0);
  EXPECT_EQ(pim.t1_ns(), t1_ns);
  const NavState predicted = predict(motion.state(t0_ns), pim);
  EXPECT_EQ(predicted.t_ns, t1_ns);
  return error(predicted, motion.state(t1_ns));
}

TEST(Preintegration, ConvergesToExactTrajectory) {
  // Window ends fall between samples at every rate, so the interpolated end pieces are used.
  const int64_t t0 = s_to_ns(0.1234567), t1 = s_to_ns(5.1234567);
  const StateError e200 = prediction_error(t0, t1, 200);
  const StateError e1000 = prediction_error(t0, t1, 1000);
  // Second-order scheme: a 5x smaller step gives ~25x smaller errors.
  EXPECT_GT(e200.rot / e1000.rot, 15.0);
  EXPECT_GT(e200.vel / e1000.vel, 15.0);
  EXPECT_GT(e200.pos / e1000.pos, 15.0);
  EXPECT_LT(e1000.rot, 5e-7);
  EXPECT_LT(e1000.vel, 5e-6);
  EXPECT_LT(e1000.pos, 1e-5);
  // EuRoC rate, 5 s of fast motion: far below the effect of the sensor noise.
  EXPECT_LT(e200.rot, 1e-5);
  EXPECT_LT(e200.pos, 2e-4);
}

TEST(Preintegration, LongWindowAtOneKilohertz) {
  const StateError e = prediction_error(0, s_to_ns(10.0), 1000);
  EXPECT_LT(e.rot, 2e-7);
  EXPECT_LT(e.vel, 2e-5);
  EXPECT_LT(e.pos, 5e-5);
}

// Gyro about a fixed axis and accel along that axis: rotations commute and the midpoint
// rotation leaves the accel unchanged, so the deltas are the integrals of the interpolated
// signal, which checks that exactly the part of each sample interval inside the window is used.
TEST(Preintegration, IntegratesExactlyTheWindowPart) {
  const int64_t period = 5'000'000;
  std::vector<ImuSample> samples;
  for (int k = 0; k <= 10; ++k) {
    ImuSample s;
    s.t_ns = k * period;
    s.gyro = Eigen::Vector3d(0, 0, 0.1 * k * k - 0.3);
    s.accel = Eigen::Vector3d(0, 0, 9.0 + std::sin(k));
    samples.push_back(s);
  }
  // Integral of the piecewise-linear signal z(t) over [t0, t1] (trapezoids on the cut pieces).
  const auto integral = [&](int64_t t0, int64_t t1, bool gyro) {
    double sum = 0.0;
    for (size_t k = 0; k + 1 < samples.size(); ++k) {
      const ImuSample &a = samples[k], &b = samples[k + 1];
      const int64_t ta = std::max(a.t_ns, t0), tb = std::min(b.t_ns, t1);
      if (ta >= tb) continue;
      const auto value = [&](int64_t t) {
        const double f = static_cast<double>(t - a.t_ns) / static_cast<double>(period);
        return gyro ? a.gyro.z() + f * (b.gyro.z() - a.gyro.z())
                    : a.accel.z() + f * (b.accel.z() - a.accel.z());
      };
      sum += 0.5 * (value(ta) + value(tb)) * ns_to_s(tb - ta);
    }
    return sum;
  };
  const int64_t t0 = 7'300'000, t1 = 41'100'000;
  const ImuPreintegration pim = preintegrate(samples, t0, t1, ImuBias{});
  EXPECT_NEAR(so3::log(pim.delta().R).z(), integral(t0, t1, true), 1e-14);
  EXPECT_NEAR(pim.delta().v.z(), integral(t0, t1, false), 1e-13);
  EXPECT_LT(pim.delta().v.head<2>().norm(), 1e-15);
  EXPECT_NEAR(pim.dt_s(), ns_to_s(t1 - t0), 1e-15);
}

TEST(Preintegration, AppendEqualsOneWindow) {
  const AnalyticMotion motion;
  const auto samples = motion.samples(0, s_to_ns(2.0), 5'000'000);
  const ImuBias bias{Eigen::Vector3d(0.01, -0.02, 0.005), Eigen::Vector3d(0.1, 0.05, -0.2)};
  // Split on a sample time: the steps of the two parts are exactly those of the whole.
  const int64_t t0 = 3'000'000, tm = 1'000'000'000, t1 = 1'900'000'000;
  ImuPreintegration first = preintegrate(samples, t0, tm, bias);
  first.append(preintegrate(samples, tm, t1, bias));
  const ImuPreintegration whole = preintegrate(samples, t0, t1, bias);
  EXPECT_EQ(first.t1_ns(), t1);
  EXPECT_LT(so3::log(first.delta().R.transpose() * whole.delta().R).norm(), 1e-13);
  EXPECT_LT((first.delta().v - whole.delta().v).norm(), 1e-12);
  EXPECT_LT((first.delta().p - whole.delta().p).norm(), 1e-12);
  EXPECT_LT((first.covariance() - whole.covariance()).norm(), 1e-12 * whole.covariance().norm());
  EXPECT_LT((first.dp_dbg() - whole.dp_dbg()).norm(), 1e-12);
  EXPECT_THROW(first.append(preintegrate(samples, t0, tm, bias)), std::invalid_argument);
}

// ---- Bias Jacobians and correction -------------------------------------------------------

class PreintegrationBias : public ::testing::Test {
 protected:
  const AnalyticMotion motion_{};
  const std::vector<ImuSample> samples_ = motion_.samples(0, s_to_ns(3.0), 5'000'000);
  const int64_t t0_ = 12'345'678, t1_ = 2'512'345'678;
  const ImuBias bias_{Eigen::Vector3d(0.02, -0.01, 0.03), Eigen::Vector3d(-0.1, 0.2, 0.05)};

  ImuPreintegration at(const ImuBias& b) const { return preintegrate(samples_, t0_, t1_, b); }
};

TEST_F(PreintegrationBias, JacobiansMatchNumericReintegration) {
  const ImuPreintegration pim = at(bias_);
  const double h = 1e-5;
  Eigen::Matrix3d dR_dbg, dv_dbg, dv_dba, dp_dbg, dp_dba;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(k);
    ImuBias gp = bias_, gm = bias_, ap = bias_, am = bias_;
    gp.gyro += e;
    gm.gyro -= e;
    ap.accel += e;
    am.accel -= e;
    const ImuDelta dgp = at(gp).delta(), dgm = at(gm).delta();
    const ImuDelta dap = at(ap).delta(), dam = at(am).delta();
    dR_dbg.col(k) = (so3::log(pim.delta().R.transpose() * dgp.R) -
                     so3::log(pim.delta().R.transpose() * dgm.R)) /
                    (2 * h);
    dv_dbg.col(k) = (dgp.v - dgm.v) / (2 * h);
    dp_dbg.col(k) = (dgp.p - dgm.p) / (2 * h);
    dv_dba.col(k) = (dap.v - dam.v) / (2 * h);
    dp_dba.col(k) = (dap.p - dam.p) / (2 * h);
  }
  const auto rel = [](const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
    return (a - b).norm() / b.norm();
  };
  EXPECT_LT(rel(pim.dR_dbg(), dR_dbg), 1e-6);
  EXPECT_LT(rel(pim.dv_dbg(), dv_dbg), 1e-6);
  EXPECT_LT(rel(pim.dp_dbg(), dp_dbg), 1e-6);
  EXPECT_LT(rel(pim.dv_dba(), dv_dba), 1e-6);
  EXPECT_LT(rel(pim.dp_dba(), dp_dba), 1e-6);
}

TEST_F(PreintegrationBias, FirstOrderCorrectionTracksReintegration) {
  const ImuPreintegration pim = at(bias_);
  // Errors of the corrected and of the uncorrected deltas w.r.t. re-integration at bias + step.
  struct Errors {
    double rot, vel, pos, rot_stale, vel_stale, pos_stale;
  };
  const auto errors = [&](const Eigen::Vector3d& dbg, const Eigen::Vector3d& dba) {
    ImuBias moved = bias_;
    moved.gyro += dbg;
    moved.accel += dba;
    const ImuDelta exact = at(moved).delta();
    const ImuDelta corr = pim.corrected(moved);
    const ImuDelta& stale = pim.delta();
    return Errors{so3::log(corr.R.transpose() * exact.R).norm(),
                  (corr.v - exact.v).norm(),
                  (corr.p - exact.p).norm(),
                  so3::log(stale.R.transpose() * exact.R).norm(),
                  (stale.v - exact.v).norm(),
                  (stale.p - exact.p).norm()};
  };
  const Eigen::Vector3d dbg(0.003, -0.002, 0.004), dba(0.05, 0.03, -0.04);
  const Errors full = errors(dbg, dba);
  const Errors half = errors(0.5 * dbg, 0.5 * dba);
  // The correction removes the first-order error (a 0.005 rad/s step over 2.5 s)...
  EXPECT_LT(full.rot, 0.01 * full.rot_stale);
  EXPECT_LT(full.vel, 0.02 * full.vel_stale);
  EXPECT_LT(full.pos, 0.02 * full.pos_stale);
  // ...and what remains is second order: halving the step quarters it.
  EXPECT_NEAR(full.rot / half.rot, 4.0, 0.5);
  EXPECT_NEAR(full.vel / half.vel, 4.0, 0.5);
  EXPECT_NEAR(full.pos / half.pos, 4.0, 0.5);
  EXPECT_NEAR(full.rot_stale / half.rot_stale, 2.0, 0.1);
}

TEST_F(PreintegrationBias, AccelBiasCorrectionIsExact) {
  const ImuPreintegration pim = at(bias_);
  ImuBias moved = bias_;
  moved.accel += Eigen::Vector3d(0.5, -0.3, 0.4);
  const ImuDelta exact = at(moved).delta();
  const ImuDelta corr = pim.corrected(moved);
  EXPECT_LT((corr.v - exact.v).norm(), 1e-12);
  EXPECT_LT((corr.p - exact.p).norm(), 1e-12);
}

TEST_F(PreintegrationBias, UpdateBiasReintegratesOnlyBeyondThreshold) {
  ImuPreintegration pim = at(bias_);
  ImuBias small = bias_;
  small.gyro.x() += 0.5 * pim.options().reintegrate_gyro_bias_change;
  EXPECT_FALSE(pim.update_bias(small));
  EXPECT_LT((pim.bias().gyro - bias_.gyro).norm(), 1e-15);

  ImuBias large = bias_;
  large.gyro.x() += 2.0 * pim.options().reintegrate_gyro_bias_change;
  large.accel.y() += 0.1;
  EXPECT_TRUE(pim.update_bias(large));
  EXPECT_LT((pim.bias().gyro - large.gyro).norm(), 1e-15);
  const ImuPreintegration fresh = at(large);
  EXPECT_LT(so3::log(pim.delta().R.transpose() * fresh.delta().R).norm(), 1e-14);
  EXPECT_LT((pim.delta().p - fresh.delta().p).norm(), 1e-13);
  EXPECT_LT((pim.dv_dbg() - fresh.dv_dbg()).norm(), 1e-13);
}

TEST_F(PreintegrationBias, BiasedSamplesPredictExactlyWithMatchingBias) {
  // The IMU sees biased data; integrating at the true bias recovers the motion.
  const auto biased = motion_.samples(0, s_to_ns(3.0), 1'000'000, bias_);
  const ImuPreintegration pim = preintegrate(biased, t0_, t1_, bias_);
  const NavState predicted = predict(motion_.state(t0_, bias_), pim);
  const NavState truth = motion_.state(t1_);
  EXPECT_LT(so3::log(predicted.q_w_b.conjugate() * truth.q_w_b).norm(), 2e-6);
  EXPECT_LT((predicted.p_w_b - truth.p_w_b).norm(), 1e-4);
  EXPECT_LT((predicted.gyro_bias - bias_.gyro).norm(), 1e-15);
}

TEST(Preintegration, BiasRandomWalkCovariance) {
  const AnalyticMotion motion;
  const ImuPreintegration pim =
      preintegrate(motion.samples(0, s_to_ns(1.0), 5'000'000), 0, s_to_ns(0.5), ImuBias{});
  const ImuNoise n;
  const Eigen::Matrix<double, 6, 6> C = pim.bias_random_walk_covariance();
  EXPECT_NEAR(C(0, 0), n.gyro_random_walk * n.gyro_random_walk * 0.5, 1e-20);
  EXPECT_NEAR(C(5, 5), n.accel_random_walk * n.accel_random_walk * 0.5, 1e-20);
  EXPECT_EQ(C(0, 1), 0.0);
}

// ---- Rejection and gap reporting ------------------------------------------------------------

class PreintegrationInput : public ::testing::Test {
 protected:
  const AnalyticMotion motion_{};
  const int64_t period_ = 5'000'000;
  const std::vector<ImuSample> clean_ = motion_.samples(0, s_to_ns(1.0), period_);
  const int64_t t0_ = 102'000'000, t1_ = 803'000'000;

  // Deltas equal to the clean run (to rounding).
  static void expect_same(const ImuPreintegration& a, const ImuPreintegration& b) {
    EXPECT_LT(so3::log(a.delta().R.transpose() * b.delta().R).norm(), 1e-14);
    EXPECT_LT((a.delta().v - b.delta().v).norm(), 1e-13);
    EXPECT_LT((a.delta().p - b.delta().p).norm(), 1e-13);
  }
};

TEST_F(PreintegrationInput, CleanInputHasNoFlags) {
  const ImuPreintegration pim = preintegrate(clean_, t0_, t1_, ImuBias{});
  const ImuIntegrationStatus& s = pim.status();
  EXPECT_EQ(s.nonfinite_rejected, 0);
  EXPECT_EQ(s.nonpositive_dt_skipped, 0);
  EXPECT_FALSE(s.has_gap());
  EXPECT_EQ(s.largest_gap_ns, period_);
  EXPECT_EQ(s.extrapolated_ns, 0);
}

TEST_F(PreintegrationInput, NonFiniteSamplesAreRejected) {
  std::vector<ImuSample> samples = clean_;
  samples[50].accel.x() = std::numeric_limits<double>::quiet_NaN();
  samples[60].gyro.z() = std::numeric_limits<double>::infinity();
  // The sample just before the window start: the one before it interpolates the start instead.
  samples[20].gyro.x() = std::numeric_limits<double>::quiet_NaN();
  ASSERT_LT(samples[20].t_ns, t0_);
  ASSERT_GT(samples[21].t_ns, t0_);
  const ImuPreintegration pim = preintegrate(samples, t0_, t1_, ImuBias{});
  EXPECT_EQ(pim.status().nonfinite_rejected, 2);  // those inside the window
  EXPECT_TRUE(pim.delta().p.allFinite());
  EXPECT_TRUE(pim.covariance().allFinite());
  // Same as leaving those samples out.
  std::vector<ImuSample> without = clean_;
  without.erase(without.begin() + 60);
  without.erase(without.begin() + 50);
  without.erase(without.begin() + 20);
  expect_same(pim, preintegrate(without, t0_, t1_, ImuBias{}));
}

TEST_F(PreintegrationInput, NonPositiveDtSamplesAreSkipped) {
  std::vector<ImuSample> samples = clean_;
  ImuSample dup = samples[70];
  dup.accel *= 2.0;  // would change the result if it were used
  samples.insert(samples.begin() + 71, dup);
  ImuSample back = samples[80];
  back.t_ns -= 2 * period_;
  samples.insert(samples.begin() + 81, back);
  const ImuPreintegration pim = preintegrate(samples, t0_, t1_, ImuBias{});
  EXPECT_EQ(pim.status().nonpositive_dt_skipped, 2);
  expect_same(pim, preintegrate(clean_, t0_, t1_, ImuBias{}));
}

TEST_F(PreintegrationInput, GapIsFlagged) {
  std::vector<ImuSample> samples = clean_;
  samples.erase(samples.begin() + 40, samples.begin() + 45);  // 6 periods without data
  const ImuPreintegration pim = preintegrate(samples, t0_, t1_, ImuBias{});
  EXPECT_TRUE(pim.status().has_gap());
  EXPECT_EQ(pim.status().gaps, 1);
  EXPECT_EQ(pim.status().largest_gap_ns, 6 * period_);
  EXPECT_EQ(pim.t1_ns(), t1_);  // integrated through, by interpolation

  // One missing sample stays under the default 15 ms threshold.
  samples = clean_;
  samples.erase(samples.begin() + 40);
  EXPECT_FALSE(preintegrate(samples, t0_, t1_, ImuBias{}).status().has_gap());
}

TEST_F(PreintegrationInput, UncoveredWindowEndsAreExtrapolatedAndFlagged) {
  const int64_t late_end = clean_.back().t_ns + 40'000'000;
  const ImuPreintegration pim = preintegrate(clean_, t0_, late_end, ImuBias{});
  EXPECT_EQ(pim.status().extrapolated_ns, 40'000'000);
  EXPECT_EQ(pim.status().gaps, 1);
  EXPECT_EQ(pim.t1_ns(), late_end);

  // A few ms short of the next sample is normal (camera ahead of IMU) and not a gap.
  const ImuPreintegration short_end =
      preintegrate(clean_, t0_, clean_.back().t_ns + 3'000'000, ImuBias{});
  EXPECT_EQ(short_end.status().extrapolated_ns, 3'000'000);
  EXPECT_FALSE(short_end.status().has_gap());
}

TEST_F(PreintegrationInput, NoSamplesIsAGap) {
  const ImuPreintegration pim = preintegrate({}, t0_, t1_, ImuBias{});
  EXPECT_TRUE(pim.status().has_gap());
  EXPECT_EQ(pim.status().largest_gap_ns, t1_ - t0_);
  EXPECT_EQ(pim.t1_ns(), t0_);
}

TEST_F(PreintegrationInput, InvalidArgumentsThrow) {
  EXPECT_THROW(preintegrate(clean_, t1_, t0_, ImuBias{}), std::invalid_argument);
  ImuPreintegration pim(0, ImuBias{});
  EXPECT_THROW(pim.integrate(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0),
               std::invalid_argument);
}

}  // namespace
}  // namespace hs
