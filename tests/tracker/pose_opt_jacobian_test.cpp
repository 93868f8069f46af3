// Analytic Jacobians and gradients of the pose optimiser's terms against central differences
// through the retraction of pose_opt_types.h.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "tests/imu/analytic_motion.h"
#include "tests/tracker/pose_opt_test_scene.h"
#include "tracker/pose_opt_inertial.h"
#include "tracker/pose_opt_visual.h"

namespace hs {
namespace {

constexpr double kStep = 1e-6;

NavState body_state() {
  NavState s;
  s.p_w_b = Eigen::Vector3d(0.4, 1.0, -0.3);
  s.q_w_b = so3::exp_quat(Eigen::Vector3d(-0.4, 0.2, 2.0));
  return s;
}

TEST(PoseOptJacobian, ReprojectionMatchesNumeric) {
  const StereoCalib calib = euroc_stereo_calib();
  const NavState truth = body_state();
  std::mt19937 rng(21);
  test::SceneOptions so;
  so.outlier_fraction = 0.0;
  so.num_observations = 40;
  so.min_depth_m = 0.5;  // near points: large rotation/translation coupling
  const test::Scene scene = test::make_scene(calib, truth, so, &rng);
  // Evaluate away from the true pose so that the residuals are not zero.
  const BodyState x = BodyState::from(test::perturbed(truth, 0.05, 0.03, &rng));
  int checked = 0;
  for (const PoseObservation& obs : scene.observations) {
    const CameraCalib& cam = obs.camera == 0 ? calib.cam0 : calib.cam1;
    const double r2max = cam.intrinsics.max_valid_radius2();
    Eigen::Vector2d r;
    Matrix26d J;
    ASSERT_TRUE(CameraView(cam, r2max, x.R_w_b, x.p_w_b).residual(obs.p_w, obs.uv, 0.05, &r, &J));
    Matrix26d J_num;
    for (int k = 0; k < 6; ++k) {
      const Vector6d d = kStep * Vector6d::Unit(k);
      const BodyState plus = x.retracted_pose(d), minus = x.retracted_pose(-d);
      Eigen::Vector2d r_plus, r_minus;
      ASSERT_TRUE(
          CameraView(cam, r2max, plus.R_w_b, plus.p_w_b).residual(obs.p_w, obs.uv, 0.05, &r_plus));
      ASSERT_TRUE(CameraView(cam, r2max, minus.R_w_b, minus.p_w_b)
                      .residual(obs.p_w, obs.uv, 0.05, &r_minus));
      J_num.col(k) = (r_plus - r_minus) / (2 * kStep);
    }
    EXPECT_LT((J - J_num).norm(), 1e-6 * J.norm()) << "analytic\n" << J << "\nnumeric\n" << J_num;
    ++checked;
  }
  EXPECT_EQ(checked, so.num_observations);
}

TEST(PoseOptJacobian, VisualGradientWithHuberMatchesNumeric) {
  const StereoCalib calib = euroc_stereo_calib();
  const NavState truth = body_state();
  std::mt19937 rng(22);
  test::SceneOptions so;  // with outliers: some terms are in the Huber's linear part
  so.num_observations = 60;
  const test::Scene scene = test::make_scene(calib, truth, so, &rng);
  const VisualTerms visual(calib, 0.05);
  const std::vector<bool> active(scene.observations.size(), true);
  const BodyState x = BodyState::from(test::perturbed(truth, 0.02, 0.01, &rng));
  const double huber = 5.991;
  Matrix6d H;
  Vector6d b;
  visual.linearise(x, scene.observations, active, huber, &H, &b);
  Vector6d b_num;
  for (int k = 0; k < 6; ++k) {
    const Vector6d d = kStep * Vector6d::Unit(k);
    b_num[k] = (visual.linearise(x.retracted_pose(d), scene.observations, active, huber, &H, &b) -
                visual.linearise(x.retracted_pose(-d), scene.observations, active, huber, &H, &b)) /
               (2 * kStep);
  }
  visual.linearise(x, scene.observations, active, huber, &H, &b);
  EXPECT_LT((b - b_num).norm(), 1e-5 * b.norm()) << b.transpose() << "\n" << b_num.transpose();
}

class InertialGradient : public ::testing::TestWithParam<bool> {};

TEST_P(InertialGradient, MatchesNumeric) {
  const bool fixed = GetParam();
  const test::AnalyticMotion motion;
  const int64_t t0 = 300'000'000, t1 = 350'000'000;
  const ImuBias lin{Eigen::Vector3d(0.01, -0.02, 0.005), Eigen::Vector3d(0.1, 0.05, -0.1)};
  const ImuPreintegration pim =
      preintegrate(motion.samples(0, 600'000'000, 5'000'000), t0, t1, lin);
  PreviousState previous;
  previous.state = motion.state(t0, lin);
  previous.fixed = fixed;
  // A dense, well-conditioned prior information.
  Eigen::Matrix<double, 15, 15> A = Eigen::Matrix<double, 15, 15>::Random();
  previous.information = A * A.transpose() + 10.0 * Matrix15d::Identity();
  const InertialTerms terms(pim, previous, default_gravity_w());

  // States off the truth and the prior mean; biases off the linearisation point.
  std::mt19937 rng(23);
  BodyState x_j = BodyState::from(test::perturbed(motion.state(t1), 0.03, 0.02, &rng));
  BodyState x_i = BodyState::from(test::perturbed(previous.state, 0.02, 0.03, &rng));
  x_j.v_w += Eigen::Vector3d(0.05, -0.02, 0.03);
  x_j.bias.gyro += Eigen::Vector3d(0.002, 0.001, -0.003);
  x_j.bias.accel += Eigen::Vector3d(-0.02, 0.03, 0.01);
  if (!fixed) {
    x_i.v_w += Eigen::Vector3d(-0.04, 0.01, 0.02);
    x_i.bias.gyro += Eigen::Vector3d(-0.003, 0.002, 0.001);
    x_i.bias.accel += Eigen::Vector3d(0.03, -0.01, 0.02);
  }

  Matrix30d H;
  Vector30d b;
  terms.linearise(x_j, x_i, &H, &b);
  const int dims = fixed ? 15 : 30;
  for (int k = 0; k < dims; ++k) {
    const Vector30d d = kStep * Vector30d::Unit(k);
    const double c_plus = terms.linearise(x_j.retracted(d.head<15>()), x_i.retracted(d.tail<15>()));
    const double c_minus =
        terms.linearise(x_j.retracted(-d.head<15>()), x_i.retracted(-d.tail<15>()));
    const double numeric = (c_plus - c_minus) / (2 * kStep);
    EXPECT_NEAR(b[k], numeric, 1e-5 * b.norm() + 1e-6) << "component " << k;
  }
  if (fixed) {
    EXPECT_EQ(H.bottomRows<15>().norm(), 0.0);
    EXPECT_EQ(b.tail<15>().norm(), 0.0);
  }
  // H is symmetric positive semi-definite.
  EXPECT_LT((H - H.transpose()).norm(), 1e-9 * H.norm());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix30d>(H).eigenvalues().minCoeff(), -1e-9 * H.norm());
}

INSTANTIATE_TEST_SUITE_P(PreviousFixedOrFree, InertialGradient, ::testing::Bool());

}  // namespace
}  // namespace hs
