// Visual-inertial mode of the pose optimiser on exact IMU samples of a smooth analytic motion.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "tests/imu/analytic_motion.h"
#include "tests/tracker/pose_opt_test_scene.h"
#include "tracker/pose_opt.h"

namespace hs {
namespace {

using test::AnalyticMotion;
using test::rotation_error_rad;

constexpr double kDeg = EIGEN_PI / 180.0;
constexpr int64_t kImuPeriodNs = 5'000'000;     // 200 Hz
constexpr int64_t kFramePeriodNs = 50'000'000;  // 20 Hz

class PoseOptInertial : public ::testing::Test {
 protected:
  const StereoCalib calib_ = euroc_stereo_calib();
  const PoseOptimizer optimizer_{calib_};
  const AnalyticMotion motion_{};
  const int64_t t0_ = 200'000'000;

  std::vector<ImuSample> samples(const ImuBias& bias = {}) const {
    return motion_.samples(0, s_to_ns(3.0), kImuPeriodNs, bias);
  }
  std::vector<PoseObservation> observations(int64_t t_ns, int count, double outliers,
                                            std::mt19937* rng) const {
    test::SceneOptions so;
    so.num_observations = count;
    so.outlier_fraction = outliers;
    return test::make_scene(calib_, motion_.state(t_ns), so, rng).observations;
  }
};

void expect_same_state(const NavState& a, const NavState& b, double tol) {
  EXPECT_LT((a.p_w_b - b.p_w_b).norm(), tol);
  EXPECT_LT(rotation_error_rad(a.q_w_b, b.q_w_b), tol);
  EXPECT_LT((a.v_w - b.v_w).norm(), tol);
  EXPECT_LT((a.gyro_bias - b.gyro_bias).norm(), tol);
  EXPECT_LT((a.accel_bias - b.accel_bias).norm(), tol);
}

TEST_F(PoseOptInertial, WithoutPointsTheEstimateIsTheImuPropagation) {
  const int64_t t1 = t0_ + kFramePeriodNs;
  const ImuBias bias{Eigen::Vector3d(0.003, -0.002, 0.001), Eigen::Vector3d(0.05, 0.02, -0.04)};
  const ImuPreintegration pim = preintegrate(samples(), t0_, t1, bias);
  for (const bool fixed : {true, false}) {
    SCOPED_TRACE(fixed ? "previous fixed" : "previous free");
    PreviousState previous;
    previous.state = motion_.state(t0_, bias);
    previous.fixed = fixed;
    previous.information = 1e4 * Matrix15d::Identity();
    const NavState prediction = predict(previous.state, pim);
    std::mt19937 rng(1);
    NavState initial = test::perturbed(prediction, 0.1, 3.0 * kDeg, &rng);
    initial.v_w += Eigen::Vector3d(0.2, -0.1, 0.1);
    initial.gyro_bias.setZero();

    PoseOptOptions options;
    options.min_step_sigma = 1e-6;  // converge far beyond the default (1% of sigma)
    const PoseOptResult r =
        PoseOptimizer(calib_, options).optimise_inertial(initial, {}, pim, previous);
    expect_same_state(r.state, prediction, 1e-8);
    EXPECT_EQ(r.state.t_ns, t1);
    EXPECT_EQ(r.status, PoseOptStatus::kTooFewInliers) << r.reason;
    EXPECT_LT(r.chi2_imu, 1e-12);
    // Without points the information comes from the IMU alone and is still positive definite.
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix15d>(r.information).eigenvalues().minCoeff(),
              0.0);
    EXPECT_GT(r.pose_covariance.diagonal().minCoeff(), 0.0);
  }
}

TEST_F(PoseOptInertial, FewPointsStayAccurateThroughTheImuTerm) {
  const int64_t t1 = t0_ + kFramePeriodNs;
  const ImuPreintegration pim = preintegrate(samples(), t0_, t1, ImuBias{});
  PreviousState previous;
  previous.state = motion_.state(t0_);
  const NavState truth = motion_.state(t1);
  std::mt19937 rng(2);
  NavState initial = test::perturbed(truth, 0.1, 3.0 * kDeg, &rng);
  initial.v_w += Eigen::Vector3d(0.2, -0.1, 0.1);
  const std::vector<PoseObservation> obs = observations(t1, 5, 0.0, &rng);

  PoseOptOptions options;
  options.min_inliers = 5;
  const PoseOptResult r =
      PoseOptimizer(calib_, options).optimise_inertial(initial, obs, pim, previous);
  ASSERT_TRUE(r.valid()) << r.reason;
  EXPECT_LT((r.state.p_w_b - truth.p_w_b).norm(), 0.002);
  EXPECT_LT(rotation_error_rad(r.state.q_w_b, truth.q_w_b), 0.02 * kDeg);
  EXPECT_LT((r.state.v_w - truth.v_w).norm(), 0.005);
  EXPECT_EQ(r.num_inliers, 5);
}

TEST_F(PoseOptInertial, BiasesConvergeOverAChainOfFrames) {
  // Biased IMU. The chain starts at a frame with the true pose and velocity but zero bias
  // estimates, under a prior that is tight on the motion and loose on the biases (as after
  // initialisation); each later frame links to the previous one under its marginal prior.
  const ImuBias truth_bias{Eigen::Vector3d(0.02, -0.015, 0.01), Eigen::Vector3d(0.15, -0.1, 0.12)};
  const std::vector<ImuSample> imu = samples(truth_bias);
  PreviousState previous;
  previous.state = motion_.state(t0_);  // zero biases
  previous.fixed = false;
  Vector15d sigma;
  sigma << Eigen::Vector3d::Constant(1e-4), Eigen::Vector3d::Constant(1e-3),
      Eigen::Vector3d::Constant(1e-3), Eigen::Vector3d::Constant(0.05),
      Eigen::Vector3d::Constant(0.5);
  previous.information = sigma.cwiseAbs2().cwiseInverse().asDiagonal();
  std::mt19937 rng(3);
  const int frames = 20;
  double nees_sum = 0.0;
  for (int f = 1; f <= frames; ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    const int64_t t = t0_ + f * kFramePeriodNs;
    const ImuBias estimate{previous.state.gyro_bias, previous.state.accel_bias};
    const ImuPreintegration pim = preintegrate(imu, previous.state.t_ns, t, estimate);
    const NavState truth = motion_.state(t, truth_bias);
    test::SceneOptions so;
    so.num_observations = 80;
    so.outlier_fraction = 0.1;
    const test::Scene scene = test::make_scene(calib_, truth, so, &rng);

    const PoseOptResult r = optimizer_.optimise_inertial(predict(previous.state, pim),
                                                         scene.observations, pim, previous);
    ASSERT_TRUE(r.valid()) << r.reason;
    for (size_t k = 0; k < scene.observations.size(); ++k) {
      if (scene.is_outlier[k]) {
        EXPECT_FALSE(r.inliers[k]);
      }
    }
    EXPECT_LT((r.state.p_w_b - truth.p_w_b).norm(), 0.01);
    EXPECT_LT(rotation_error_rad(r.state.q_w_b, truth.q_w_b), 0.1 * kDeg);
    Vector6d e;
    e << so3::log(truth.q_w_b.inverse() * r.state.q_w_b), r.state.p_w_b - truth.p_w_b;
    nees_sum += e.dot(r.pose_covariance.ldlt().solve(e));
    previous = {r.state, false, r.information};
  }
  const NavState& last = previous.state;
  const double gyro_before = truth_bias.gyro.norm(), accel_before = truth_bias.accel.norm();
  const double gyro_after = (last.gyro_bias - truth_bias.gyro).norm();
  const double accel_after = (last.accel_bias - truth_bias.accel).norm();
  std::printf(
      "bias error after %d frames: gyro %.5f (from %.5f) rad/s, accel %.4f (from %.4f) "
      "m/s^2, mean pose NEES %.2f\n",
      frames, gyro_after, gyro_before, accel_after, accel_before, nees_sum / frames);
  EXPECT_LT(gyro_after, 0.1 * gyro_before);
  EXPECT_LT(accel_after, 0.1 * accel_before);
  // The reported pose covariance is consistent with the errors (mean NEES ~ 6 DoF).
  EXPECT_LT(nees_sum / frames, 12.0);
}

TEST_F(PoseOptInertial, RejectsAPreintegrationOverAnotherWindow) {
  const int64_t t1 = t0_ + kFramePeriodNs;
  const ImuPreintegration pim = preintegrate(samples(), t0_, t1, ImuBias{});
  PreviousState previous;
  previous.state = motion_.state(t0_ + 1);
  EXPECT_THROW(optimizer_.optimise_inertial(motion_.state(t1), {}, pim, previous),
               std::invalid_argument);
  previous.state = motion_.state(t0_);
  EXPECT_THROW(optimizer_.optimise_inertial(motion_.state(t1 + 1), {}, pim, previous),
               std::invalid_argument);
}

}  // namespace
}  // namespace hs
