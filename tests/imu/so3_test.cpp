#include "common/imu/so3.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace hs {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Rotation vectors covering zero, tiny, the small-angle switch, generic and near-pi angles.
std::vector<Eigen::Vector3d> test_vectors() {
  std::vector<Eigen::Vector3d> out;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double angles[] = {0.0, 1e-12, 1e-8, 1e-5,       9.9e-3,     1.01e-2,
                           0.3, 1.0,   2.5,  kPi - 1e-3, kPi - 1e-6, kPi - 1e-9};
  for (const double angle : angles) {
    for (int k = 0; k < 5; ++k) {
      const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
      out.push_back(angle * axis);
    }
  }
  return out;
}

// Reference rotation from Eigen's angle-axis (closed form, independent of so3.cpp).
Eigen::Matrix3d reference_exp(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  if (angle == 0.0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, phi / angle).toRotationMatrix();
}

TEST(So3, HatVee) {
  const Eigen::Vector3d w(0.3, -1.2, 2.0);
  const Eigen::Vector3d x(-0.7, 0.4, 1.1);
  EXPECT_LT((so3::hat(w) * x - w.cross(x)).norm(), 1e-15);
  EXPECT_LT((so3::vee(so3::hat(w)) - w).norm(), 1e-15);
  EXPECT_LT((so3::hat(w) + so3::hat(w).transpose()).norm(), 1e-15);
}

TEST(So3, ExpMatchesAngleAxisAndQuaternion) {
  for (const Eigen::Vector3d& phi : test_vectors()) {
    const Eigen::Matrix3d R = so3::exp(phi);
    EXPECT_LT((R - reference_exp(phi)).norm(), 1e-14) << phi.transpose();
    EXPECT_LT((so3::exp_quat(phi).toRotationMatrix() - R).norm(), 1e-14) << phi.transpose();
    EXPECT_NEAR(so3::exp_quat(phi).norm(), 1.0, 1e-15);
    EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  }
}

TEST(So3, LogInvertsExp) {
  for (const Eigen::Vector3d& phi : test_vectors()) {
    // Relative accuracy at tiny angles, absolute (machine precision) elsewhere.
    const double tol = std::max(1e-12 * phi.norm(), 1e-14);
    const Eigen::Vector3d from_matrix = so3::log(reference_exp(phi));
    const Eigen::Vector3d from_quat = so3::log(so3::exp_quat(phi));
    EXPECT_LT((from_matrix - phi).norm(), tol) << phi.transpose();
    EXPECT_LT((from_quat - phi).norm(), tol) << phi.transpose();
  }
}

TEST(So3, LogReturnsAngleUpToPi) {
  // A rotation by pi + 0.2 about z is a rotation by pi - 0.2 about -z.
  const Eigen::Vector3d phi = so3::log(reference_exp(Eigen::Vector3d(0, 0, kPi + 0.2)));
  EXPECT_LT((phi - Eigen::Vector3d(0, 0, -(kPi - 0.2))).norm(), 1e-12);
  // Exactly pi: either sign of the axis is the same rotation.
  const Eigen::Vector3d at_pi = so3::log(reference_exp(Eigen::Vector3d(kPi, 0, 0)));
  EXPECT_NEAR(at_pi.norm(), kPi, 1e-12);
  EXPECT_LT((reference_exp(at_pi) - reference_exp(Eigen::Vector3d(kPi, 0, 0))).norm(), 1e-12);
  // A negative-w quaternion gives the same rotation vector.
  const Eigen::Quaterniond q = so3::exp_quat(Eigen::Vector3d(0.1, -0.4, 0.2));
  Eigen::Quaterniond q_neg(-q.w(), -q.x(), -q.y(), -q.z());
  EXPECT_LT((so3::log(q_neg) - Eigen::Vector3d(0.1, -0.4, 0.2)).norm(), 1e-14);
}

// Numeric right Jacobian: column k of Log(Exp(phi)^T Exp(phi + h e_k)) / h, central.
Eigen::Matrix3d numeric_right_jacobian(const Eigen::Vector3d& phi) {
  const double h = 1e-6;
  Eigen::Matrix3d J;
  const Eigen::Matrix3d Rt = reference_exp(phi).transpose();
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d d = h * Eigen::Vector3d::Unit(k);
    J.col(k) =
        (so3::log(Rt * reference_exp(phi + d)) - so3::log(Rt * reference_exp(phi - d))) / (2.0 * h);
  }
  return J;
}

TEST(So3, RightJacobianMatchesNumeric) {
  for (const Eigen::Vector3d& phi : test_vectors()) {
    if (phi.norm() > 3.0)
      continue;  // Log of the tiny perturbation is well-conditioned anyway,
                 // but Exp(phi +- h) crosses pi there.
    const Eigen::Matrix3d Jr = so3::right_jacobian(phi);
    EXPECT_LT((Jr - numeric_right_jacobian(phi)).norm(), 1e-8) << phi.transpose();
    EXPECT_LT((so3::right_jacobian_inverse(phi) * Jr - Eigen::Matrix3d::Identity()).norm(), 1e-12)
        << phi.transpose();
  }
}

TEST(So3, RightJacobianInverseFiniteAtPi) {
  const Eigen::Vector3d phi(0.0, kPi, 0.0);
  const Eigen::Matrix3d Jr_inv = so3::right_jacobian_inverse(phi);
  EXPECT_TRUE(Jr_inv.allFinite());
  EXPECT_LT((Jr_inv * so3::right_jacobian(phi) - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(So3, LogLinearisation) {
  // Log(Exp(phi) Exp(d)) ~= phi + Jr^-1(phi) d, to second order in d.
  const Eigen::Vector3d phi(0.4, -1.1, 0.7);
  const Eigen::Vector3d d(1e-5, -2e-5, 1.5e-5);
  const Eigen::Vector3d lhs = so3::log(so3::exp(phi) * so3::exp(d));
  EXPECT_LT((lhs - phi - so3::right_jacobian_inverse(phi) * d).norm(), 1e-9);
}

}  // namespace
}  // namespace hs
