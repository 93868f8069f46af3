#include "tracker/pose_opt.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "tests/tracker/pose_opt_test_scene.h"

namespace hs {
namespace {

using test::make_scene;
using test::perturbed;
using test::rotation_error_rad;
using test::Scene;
using test::SceneOptions;

constexpr double kDeg = EIGEN_PI / 180.0;

NavState true_state() {
  NavState s;
  s.t_ns = 1'000'000'000;
  s.p_w_b = Eigen::Vector3d(1.0, -2.0, 0.8);
  s.q_w_b = so3::exp_quat(Eigen::Vector3d(0.3, -0.2, 1.1));
  s.v_w = Eigen::Vector3d(0.5, 0.1, 0.0);
  return s;
}

// Pose error [rotation (body), position (world)] in the tangent of the covariance.
Vector6d pose_error(const NavState& estimate, const NavState& truth) {
  Vector6d e;
  e << so3::log(truth.q_w_b.inverse() * estimate.q_w_b), estimate.p_w_b - truth.p_w_b;
  return e;
}

TEST(PoseOpt, RecoversPoseWithNoiseAndOutliers) {
  const StereoCalib calib = euroc_stereo_calib();
  const PoseOptimizer optimizer(calib);
  const NavState truth = true_state();
  for (unsigned seed = 1; seed <= 10; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 rng(seed);
    const Scene scene = make_scene(calib, truth, SceneOptions{}, &rng);
    const NavState initial = perturbed(truth, 0.10, 3.0 * kDeg, &rng);
    const PoseOptResult r = optimizer.optimise_pose(initial, scene.observations);

    ASSERT_TRUE(r.valid()) << r.reason;
    // The noise alone gives ~2 mm / 0.017 deg per axis (1 sigma) here; the NEES check below is
    // the tight one.
    EXPECT_LT((r.state.p_w_b - truth.p_w_b).norm(), 0.01);
    EXPECT_LT(rotation_error_rad(r.state.q_w_b, truth.q_w_b), 0.1 * kDeg);
    // Every gross outlier is flagged; the chi2 test at 95% keeps nearly all true inliers.
    int kept = 0;
    for (size_t k = 0; k < scene.observations.size(); ++k) {
      if (scene.is_outlier[k]) {
        EXPECT_FALSE(r.inliers[k]) << "observation " << k;
      }
      kept += !scene.is_outlier[k] && r.inliers[k];
    }
    const int true_inliers = static_cast<int>(scene.observations.size()) - scene.num_outliers();
    EXPECT_GE(kept, 0.9 * true_inliers);
    EXPECT_EQ(r.num_inliers, kept);
    EXPECT_LT(r.rms_px, 1.5);
    EXPECT_LE(r.chi2_max, optimizer.options().chi2_threshold);
    // Velocity, biases and time are not touched in this mode.
    EXPECT_EQ(r.state.t_ns, initial.t_ns);
    EXPECT_EQ(r.state.v_w, initial.v_w);
    // The error is consistent with the reported covariance (chi2 with 6 DoF, 99.9%: 22.5).
    const Vector6d e = pose_error(r.state, truth);
    EXPECT_LT(e.dot(r.pose_covariance.ldlt().solve(e)), 22.5);
  }
}

TEST(PoseOpt, ExactWithoutNoise) {
  const StereoCalib calib = euroc_stereo_calib();
  PoseOptOptions options;
  options.min_step_sigma = 1e-6;  // converge far beyond the default (1% of sigma)
  const PoseOptimizer optimizer(calib, options);
  const NavState truth = true_state();
  std::mt19937 rng(7);
  SceneOptions so;
  so.outlier_fraction = 0.0;
  so.noise_scale = 0.0;
  const Scene scene = make_scene(calib, truth, so, &rng);
  const PoseOptResult r =
      optimizer.optimise_pose(perturbed(truth, 0.1, 3.0 * kDeg, &rng), scene.observations);
  ASSERT_TRUE(r.valid()) << r.reason;
  EXPECT_EQ(r.num_inliers, so.num_observations);
  EXPECT_LT((r.state.p_w_b - truth.p_w_b).norm(), 1e-8);
  EXPECT_LT(rotation_error_rad(r.state.q_w_b, truth.q_w_b), 1e-9);
  EXPECT_LT(r.rms_px, 1e-6);
}

TEST(PoseOpt, CovarianceMatchesSpreadOverTrials) {
  // The mean Mahalanobis norm of the error over many noise draws is the DoF (6).
  const StereoCalib calib = euroc_stereo_calib();
  const PoseOptimizer optimizer(calib);
  const NavState truth = true_state();
  SceneOptions so;
  so.outlier_fraction = 0.0;
  so.num_observations = 100;
  double sum = 0.0;
  const int trials = 200;
  for (int t = 0; t < trials; ++t) {
    std::mt19937 rng(100 + t);
    const Scene scene = make_scene(calib, truth, so, &rng);
    const PoseOptResult r = optimizer.optimise_pose(truth, scene.observations);
    const Vector6d e = pose_error(r.state, truth);
    sum += e.dot(r.pose_covariance.ldlt().solve(e));
  }
  // Chi2 rejections of ~5% of the inliers make it slightly optimistic; within 25%.
  EXPECT_NEAR(sum / trials, 6.0, 1.5);
}

TEST(PoseOpt, FailureCheckTooFewInliers) {
  const StereoCalib calib = euroc_stereo_calib();
  PoseOptOptions options;
  options.min_inliers = 15;
  const PoseOptimizer optimizer(calib, options);
  const NavState truth = true_state();
  std::mt19937 rng(3);
  SceneOptions so;
  so.num_observations = 20;
  so.outlier_fraction = 0.5;  // 10 inliers
  const Scene scene = make_scene(calib, truth, so, &rng);
  const PoseOptResult r = optimizer.optimise_pose(truth, scene.observations);
  EXPECT_EQ(r.status, PoseOptStatus::kTooFewInliers) << r.reason;
  EXPECT_FALSE(r.valid());
  EXPECT_LE(r.num_inliers, 14);
  EXPECT_NE(r.reason.find("N_min"), std::string::npos);
}

TEST(PoseOpt, FailureCheckHugeNoise) {
  // The observations claim 0.7-1.2 px but are 20x noisier: most fail the chi2 test and what
  // is left either is too few or reprojects badly.
  const StereoCalib calib = euroc_stereo_calib();
  const PoseOptimizer optimizer(calib);
  const NavState truth = true_state();
  std::mt19937 rng(5);
  SceneOptions so;
  so.outlier_fraction = 0.0;
  so.noise_scale = 20.0;
  so.num_observations = 60;
  const Scene scene = make_scene(calib, truth, so, &rng);
  const PoseOptResult r = optimizer.optimise_pose(truth, scene.observations);
  EXPECT_FALSE(r.valid());
  EXPECT_TRUE(r.status == PoseOptStatus::kTooFewInliers || r.status == PoseOptStatus::kRmsTooHigh)
      << to_string(r.status);

  // The RMS check alone: with every observation an inlier (huge chi2 threshold) the RMS is
  // ~20 px.
  PoseOptOptions lax;
  lax.chi2_threshold = 1e9;
  const PoseOptResult r2 = PoseOptimizer(calib, lax).optimise_pose(truth, scene.observations);
  EXPECT_EQ(r2.status, PoseOptStatus::kRmsTooHigh) << r2.reason;
  EXPECT_GT(r2.rms_px, 10.0);
}

TEST(PoseOpt, FailureCheckDivergedFarFromInitialGuess) {
  // An initial guess 1.5 m off converges, but further than max_translation_m from where the
  // tracker expected the frame: the check rejects it.
  const StereoCalib calib = euroc_stereo_calib();
  const PoseOptimizer optimizer(calib);
  const NavState truth = true_state();
  std::mt19937 rng(9);
  SceneOptions so;
  so.outlier_fraction = 0.0;
  const Scene scene = make_scene(calib, truth, so, &rng);
  NavState initial = truth;
  initial.p_w_b += Eigen::Vector3d(0.0, 0.0, 1.5);
  const PoseOptResult r = optimizer.optimise_pose(initial, scene.observations);
  EXPECT_EQ(r.status, PoseOptStatus::kDiverged) << r.reason;
}

TEST(PoseOpt, BadInputsAreOutliersOrNonFinite) {
  const StereoCalib calib = euroc_stereo_calib();
  const PoseOptimizer optimizer(calib);
  const NavState truth = true_state();
  std::mt19937 rng(11);
  SceneOptions so;
  so.outlier_fraction = 0.0;
  so.num_observations = 50;
  Scene scene = make_scene(calib, truth, so, &rng);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  scene.observations[0].uv.x() = nan;
  scene.observations[1].p_w.z() = nan;
  scene.observations[2].camera = 2;
  scene.observations[3].sigma_px = 0.0;
  // A point behind the cameras.
  const Eigen::Isometry3d T_w_c0 =
      Eigen::Translation3d(truth.p_w_b) * truth.q_w_b * calib.cam0.T_b_c;
  scene.observations[4].p_w = T_w_c0 * Eigen::Vector3d(0.1, 0.2, -3.0);
  scene.observations[4].camera = 0;
  const PoseOptResult r = optimizer.optimise_pose(truth, scene.observations);
  ASSERT_TRUE(r.valid()) << r.reason;
  for (int k = 0; k < 5; ++k) EXPECT_FALSE(r.inliers[k]) << k;
  EXPECT_LT((r.state.p_w_b - truth.p_w_b).norm(), 0.02);

  NavState bad = truth;
  bad.p_w_b.x() = nan;
  const PoseOptResult r_bad = optimizer.optimise_pose(bad, scene.observations);
  EXPECT_EQ(r_bad.status, PoseOptStatus::kNonFinite);
  EXPECT_EQ(r_bad.inliers.size(), scene.observations.size());

  // No observations at all: nothing to estimate, the pose stays and the check fails.
  const PoseOptResult r_none = optimizer.optimise_pose(truth, {});
  EXPECT_EQ(r_none.status, PoseOptStatus::kTooFewInliers);
  EXPECT_EQ(r_none.state.p_w_b, truth.p_w_b);
  EXPECT_EQ(r_none.pose_covariance, Matrix6d::Zero());
}

TEST(PoseOpt, RejectsBadOptions) {
  PoseOptOptions o;
  o.rounds = 0;
  EXPECT_THROW(PoseOptimizer(euroc_stereo_calib(), o), std::invalid_argument);
  o = PoseOptOptions{};
  o.chi2_threshold = 0.0;
  EXPECT_THROW(PoseOptimizer(euroc_stereo_calib(), o), std::invalid_argument);
}

}  // namespace
}  // namespace hs
