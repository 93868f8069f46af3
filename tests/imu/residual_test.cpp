#include "common/imu/imu_residual.h"

#include <gtest/gtest.h>

#include <functional>

#include "common/imu/so3.h"
#include "tests/imu/analytic_motion.h"

namespace hs {
namespace {

using test::AnalyticMotion;

struct States {
  Eigen::Matrix3d R_i, R_j;
  Eigen::Vector3d p_i, v_i, p_j, v_j;
  ImuBias bias;
};

class ImuResidual : public ::testing::Test {
 protected:
  const AnalyticMotion motion_{};
  const int64_t t0_ = 200'000'000, t1_ = 1'700'000'000;
  const ImuBias lin_{Eigen::Vector3d(0.01, 0.02, -0.01), Eigen::Vector3d(0.1, -0.1, 0.2)};
  const ImuPreintegration pim_ =
      preintegrate(motion_.samples(0, s_to_ns(2.0), 5'000'000), t0_, t1_, lin_);

  Vector9d residual(const States& s, ImuResidualJacobians* J = nullptr) const {
    return imu_residual(pim_, s.R_i, s.p_i, s.v_i, s.R_j, s.p_j, s.v_j, s.bias, default_gravity_w(),
                        J);
  }

  // States near the truth but off it, and a bias off the linearisation point, so that every
  // term of the Jacobians is exercised.
  States perturbed_truth() const {
    const NavState i = motion_.state(t0_), j = motion_.state(t1_);
    States s;
    s.R_i = i.q_w_b.toRotationMatrix() * so3::exp(Eigen::Vector3d(0.05, -0.03, 0.04));
    s.R_j = j.q_w_b.toRotationMatrix() * so3::exp(Eigen::Vector3d(-0.02, 0.06, 0.01));
    s.p_i = i.p_w_b + Eigen::Vector3d(0.1, -0.05, 0.02);
    s.v_i = i.v_w + Eigen::Vector3d(-0.03, 0.02, 0.05);
    s.p_j = j.p_w_b + Eigen::Vector3d(-0.04, 0.08, -0.1);
    s.v_j = j.v_w + Eigen::Vector3d(0.06, -0.01, 0.02);
    s.bias.gyro = lin_.gyro + Eigen::Vector3d(0.004, -0.003, 0.002);
    s.bias.accel = lin_.accel + Eigen::Vector3d(-0.05, 0.02, 0.03);
    return s;
  }
};

// Central differences of the residual for a perturbation `apply(states, delta)`.
Matrix93d numeric(const std::function<Vector9d(const States&)>& f, const States& s0,
                  const std::function<void(States&, const Eigen::Vector3d&)>& apply) {
  const double h = 1e-6;
  Matrix93d J;
  for (int k = 0; k < 3; ++k) {
    States plus = s0, minus = s0;
    apply(plus, h * Eigen::Vector3d::Unit(k));
    apply(minus, -h * Eigen::Vector3d::Unit(k));
    J.col(k) = (f(plus) - f(minus)) / (2 * h);
  }
  return J;
}

TEST_F(ImuResidual, ZeroAtTruthAndAtPrediction) {
  const NavState i = motion_.state(t0_), j = motion_.state(t1_);
  const auto at_truth = [&](const ImuPreintegration& pim, const ImuBias& bias) {
    return imu_residual(pim, i.q_w_b.toRotationMatrix(), i.p_w_b, i.v_w, j.q_w_b.toRotationMatrix(),
                        j.p_w_b, j.v_w, bias, default_gravity_w());
  };
  // The samples are unbiased: at the true (zero) bias only the 200 Hz discretisation error of
  // the exact trajectory remains.
  const ImuPreintegration unbiased =
      preintegrate(motion_.samples(0, s_to_ns(2.0), 5'000'000), t0_, t1_, ImuBias{});
  const Vector9d r_truth = at_truth(unbiased, ImuBias{});
  EXPECT_LT(r_truth.head<3>().norm(), 1e-5);
  EXPECT_LT(r_truth.tail<6>().norm(), 1e-4);
  // A wrong bias shows up in the residual.
  EXPECT_GT(at_truth(unbiased, lin_).norm(), 1e-2);
  // Predicted states are consistent with the preintegration by construction.
  const States off = perturbed_truth();
  NavState s_i;
  s_i.t_ns = t0_;
  s_i.q_w_b = Eigen::Quaterniond(off.R_i);
  s_i.p_w_b = off.p_i;
  s_i.v_w = off.v_i;
  s_i.gyro_bias = off.bias.gyro;
  s_i.accel_bias = off.bias.accel;
  const NavState s_j = predict(s_i, pim_);
  const Vector9d r_pred = imu_residual(pim_, s_i.q_w_b.toRotationMatrix(), s_i.p_w_b, s_i.v_w,
                                       s_j.q_w_b.toRotationMatrix(), s_j.p_w_b, s_j.v_w,
                                       ImuBias{s_i.gyro_bias, s_i.accel_bias}, default_gravity_w());
  EXPECT_LT(r_pred.norm(), 1e-12);
}

TEST_F(ImuResidual, JacobiansMatchNumeric) {
  const States s0 = perturbed_truth();
  ImuResidualJacobians J;
  residual(s0, &J);
  const auto f = [this](const States& s) { return residual(s); };
  using D = const Eigen::Vector3d&;
  const Matrix93d n_R_i = numeric(f, s0, [](States& s, D d) { s.R_i = s.R_i * so3::exp(d); });
  const Matrix93d n_R_j = numeric(f, s0, [](States& s, D d) { s.R_j = s.R_j * so3::exp(d); });
  const Matrix93d n_p_i = numeric(f, s0, [](States& s, D d) { s.p_i += d; });
  const Matrix93d n_v_i = numeric(f, s0, [](States& s, D d) { s.v_i += d; });
  const Matrix93d n_p_j = numeric(f, s0, [](States& s, D d) { s.p_j += d; });
  const Matrix93d n_v_j = numeric(f, s0, [](States& s, D d) { s.v_j += d; });
  const Matrix93d n_bg = numeric(f, s0, [](States& s, D d) { s.bias.gyro += d; });
  const Matrix93d n_ba = numeric(f, s0, [](States& s, D d) { s.bias.accel += d; });
  const double tol = 1e-7;
  EXPECT_LT((J.R_i - n_R_i).norm(), tol * (1 + n_R_i.norm())) << J.R_i << "\n\n" << n_R_i;
  EXPECT_LT((J.R_j - n_R_j).norm(), tol * (1 + n_R_j.norm())) << J.R_j << "\n\n" << n_R_j;
  EXPECT_LT((J.p_i - n_p_i).norm(), tol * (1 + n_p_i.norm()));
  EXPECT_LT((J.v_i - n_v_i).norm(), tol * (1 + n_v_i.norm()));
  EXPECT_LT((J.p_j - n_p_j).norm(), tol * (1 + n_p_j.norm()));
  EXPECT_LT((J.v_j - n_v_j).norm(), tol * (1 + n_v_j.norm()));
  EXPECT_LT((J.bg - n_bg).norm(), tol * (1 + n_bg.norm())) << J.bg << "\n\n" << n_bg;
  EXPECT_LT((J.ba - n_ba).norm(), tol * (1 + n_ba.norm()));
}

TEST_F(ImuResidual, ResidualWithoutJacobiansIsTheSame) {
  const States s0 = perturbed_truth();
  ImuResidualJacobians J;
  EXPECT_EQ(residual(s0), residual(s0, &J));
}

}  // namespace
}  // namespace hs
